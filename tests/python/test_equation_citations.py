"""Equation numbers repeat across the papers (issue 17), so every line under cpp/, addon/hairlod/ and
tests/ that cites an equation must name its paper on the same line (docs/ARCHITECTURE.md Sec. 3).

Pure text: no import of hairlod, no build needed.
"""

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ROOTS = ("cpp", "addon/hairlod", "tests")
SUFFIXES = {".cpp", ".h", ".hpp", ".cc", ".py", ".glsl", ".txt", ".cmake", ".md"}
THIS_FILE = Path(__file__).resolve()

# An equation citation: "Eq." or "Eqs." (optionally "Table/Eq.") followed by a number.
CITATION = re.compile(r"\bEqs?\.\s?\(?\d")

# Accepted paper names: the short forms of docs/ARCHITECTURE.md Sec. 3 and the longer forms
# already used in the code.
PAPERS = [
    r"Huang( et al\.)? 2025", r"hair-lod-aggregated-bcsdf",  # aggregated BCSDF / hair LoD
    r"Xu( et al\.)? 2011", r"circular-gaussian-hair-env-lighting",  # circular Gaussians, SRBF lights
    r"Bhokare( et al\.)? 2024", r"Yuksel( et al\.)? 2009", r"hair-meshes-realtime",  # hair meshes
    r"\bthesis\b", r"realtime-pbr-hair-thesis", r"Gonzalez Jimenez",  # real-time PBR hair thesis
    r"Yuksel( et al\.)? 2015",  # Poisson sampling by sample elimination
    r"Chiang( et al\.)? 2016", r"d'Eon( et al\.)? 2011", r"Zinke( et al\.)? 2008",
    r"Marschner( et al\.)? 2003", r"Meyer( et al\.)? 2010", r"\bFLIP\b",
    r"Huang( et al\.)? 2022", r"Heitz( et al\.)? 2018",  # the microfacet fibre and its GGX sampling
]
NAMED = re.compile("|".join(PAPERS))


def cited_lines():
    for root in ROOTS:
        for path in sorted((REPO / root).rglob("*")):
            if not path.is_file() or path.suffix not in SUFFIXES or path.resolve() == THIS_FILE:
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            for number, line in enumerate(text.splitlines(), 1):
                if CITATION.search(line):
                    yield path.relative_to(REPO), number, line


def test_scan_finds_citations():
    # Guards against a scan that silently reads nothing (moved folders, wrong root).
    assert sum(1 for _ in cited_lines()) > 100


def test_every_equation_citation_names_its_paper():
    unnamed = [f"{path}:{number}: {line.strip()}" for path, number, line in cited_lines()
               if not NAMED.search(line)]
    assert not unnamed, ("equation numbers collide across papers; name the paper on the same line "
                         "(docs/ARCHITECTURE.md Sec. 3):\n" + "\n".join(unnamed))
