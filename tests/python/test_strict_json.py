"""strict_json and memory_budget: bounded input, strict output, the budget read from the environment."""

import json
import os

import pytest

from hairlod import memory_budget, strict_json


@pytest.mark.parametrize("text, message", [
    ("[" * 100_000 + "]" * 100_000, "nested more than 64 levels"),
    ('{"a":' * 65 + "1" + "}" * 65, "nested more than 64 levels"),
    ('{"face": 100000000000000000000}', "integer 100000000000000000000 is too large"),
    ('{"x": 1e400}', "number 1e400 is out of range"),
    ('{"x": -1e400}', "number -1e400 is out of range"),
    ('{"x": NaN}', "NaN is not a JSON number"),
    ('{"x": Infinity}', "Infinity is not a JSON number"),
    ('{"x": 1', "not valid JSON"),
    (b"\xff\xfe{}", "not UTF-8"),
    ("", "not valid JSON"),
])
def test_bad_json_is_one_value_error_naming_the_file(text, message):
    with pytest.raises(ValueError, match=message) as error:
        strict_json.loads(text, "hair.json")
    assert str(error.value).startswith("hair.json: ")


def test_within_bounds_reads_as_json_does():
    text = '{"a": [' * 30 + "1, -9223372036854775807, 2.5e300, \"[[[\\\"{{\"" + "]}" * 30
    assert strict_json.loads(text, "x") == json.loads(text)


def test_unreadable_file_names_it(tmp_path):
    with pytest.raises(ValueError, match=f"{tmp_path / 'missing.json'} \\(cameras\\): cannot read"):
        strict_json.load(tmp_path / "missing.json", "cameras")


def test_output_refuses_non_finite_numbers():
    with pytest.raises(ValueError):
        strict_json.dumps({"width_px": float("inf")})
    assert strict_json.dumps({"width_px": 2.0}) == '{"width_px": 2.0}'


def test_budget_from_the_environment(monkeypatch):
    monkeypatch.setenv(memory_budget.ENVIRONMENT_VARIABLE, "512M")
    assert memory_budget.budget_bytes() == 512 << 20
    monkeypatch.setenv(memory_budget.ENVIRONMENT_VARIABLE, "2gb")
    assert memory_budget.budget_bytes() == 2 << 30
    memory_budget.check(2 << 30, "fits")
    with pytest.raises(memory_budget.MemoryBudgetError, match="--count needs about 3.0 GB, more than the memory "
                                                              "budget of 2.0 GB"):
        memory_budget.check(3 << 30, "--count")
    for bad in ("lots", "-1G", "0", "infG"):
        monkeypatch.setenv(memory_budget.ENVIRONMENT_VARIABLE, bad)
        with pytest.raises(ValueError, match="HAIRLOD_MEMORY_BUDGET"):
            memory_budget.budget_bytes()
    monkeypatch.delenv(memory_budget.ENVIRONMENT_VARIABLE)
    assert memory_budget.budget_bytes() > 0


def test_only_regular_files_of_bounded_size_are_read(tmp_path, monkeypatch):
    fifo = tmp_path / "cameras.json"
    os.mkfifo(fifo)
    for path in (fifo, "/dev/zero", tmp_path):
        with pytest.raises(ValueError, match="not a regular file|cannot read"):
            strict_json.load(path, "cameras")
    big = tmp_path / "big.json"
    big.write_text("[" + "0," * 600 + "0]")
    monkeypatch.setattr(strict_json, "MAX_FILE_BYTES", 1000)
    with pytest.raises(ValueError, match="larger than"):
        strict_json.load(big)
