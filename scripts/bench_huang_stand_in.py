"""Which Chiang fibre should stand in for a Huang (Blender 4.x) hair material: renders the LoD test
scenes (the real Ratboy mohawk and 5000 generated wavy strands, mid view) with the Huang fibre
path-traced as the reference, then `pt`, `ds` and `lod` through the Chiang stand-in of
hairlod/bcsdf/chiang_stand_in.h and through a Chiang fibre with the material's own absorption, and
prints the blurred PSNR and the mean hair colour error per channel of each (docs/lod-quality.md, "Blender 4.x hair").

    python3 scripts/bench_huang_stand_in.py [--width 96 --spp 64 --reference-spp 256]
"""

import argparse
import os
import sys


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "addon"))
from hairlod import generate_strands, hair_params, hairmesh, io, lod, render  # noqa: E402

REPO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--width", type=int, default=96)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--reference-spp", type=int, default=256)
    args = parser.parse_args()
    hairs = {"Ratboy": io.read(os.path.join(REPO, "examples", "data", "tressfx", "Ratboy_mohawk.tfx")),
             "wavy 5k": generate_strands(hairmesh.read(os.path.join(REPO, "examples", "data", "wavy_cap.hairmesh.json")),
                                         count=5000, vertices=17, seed=3)}
    print("| hair | melanin | method | stand-in: blurred PSNR dB, colour % | same absorption: blurred PSNR dB, colour % |")
    print("| --- | --- | --- | --- | --- |")
    for name, strands in hairs.items():
        asset = lod.build_lod(strands)
        mask = render.render(strands, "pt", view="mid", width=args.width, spp=8, seed=1, coverage_only=True)["image"][..., 0] < 0.5
        for melanin in (0.6, 0.15):
            huang = hair_params.params_to_dict(hair_params.from_principled_hair(model="HUANG", parametrization="MELANIN",
                                                                                  melanin=melanin))
            reference = render.render(strands, "pt", view="mid", width=args.width, spp=args.reference_spp, params=huang,
                                      seed=7)["image"]
            candidates = (("stand-in", dict(huang, fibre="chiang")),
                          ("same absorption", dict(huang, fibre="chiang", sigma_a=huang["huang_sigma_a"])))
            for method in ("pt", "ds", "lod"):
                cells = []
                for _, params in candidates:
                    image = render.render(strands, method, view="mid", width=args.width, spp=args.spp, params=params, seed=1,
                                          asset=asset if method == "lod" else None)["image"]
                    error = 100.0 * (image[mask].mean(axis=0) / reference[mask].mean(axis=0) - 1.0)
                    cells.append(f"{render.blurred_psnr(image, reference):.1f}, " + " / ".join(f"{e:+.0f}" for e in error))
                print(f"| {name} | {melanin} | {method} | {cells[0]} | {cells[1]} |", flush=True)


if __name__ == "__main__":
    main()
