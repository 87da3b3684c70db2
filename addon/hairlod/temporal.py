"""Temporal stability of the LoD on animated hair (hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4 and
Fig. 9's measure of popping): the hair at successive frames rendered with every strand and with the
LoD skinned to each frame's guides, by the Embree renderer.

bench_animation() renders each frame twice from one camera (framed on the first frame): 'pt' with every
strand (the reference) and 'lod', the asset's selection skinned to the frame's guides. Both use the same
seed at every frame, so their noise does not flicker from frame to frame and the adjacent-frame PSNR
measures what changes on screen: the motion, and for the LoD any popping between levels or thick hairs
lagging behind the strands. It reports per frame the segments, seconds and the LoD's blurred PSNR
against the reference, and per method the blurred PSNR of each frame against the previous one, all
over the box the hair covers in some frame (render.blurred_psnr on whole 4 x 4 blocks); the
LoD keeps the look in motion when its adjacent-frame PSNRs are within about 1 dB of the strands'.
No assertions: a benchmark, not a test.
"""

import time

import numpy as np

from . import lod, render

__all__ = ["bench_animation", "bend", "turn"]


def turn(points, angle, centre=(0.0, 0.0, 0.5)):
    """Points [..., 3] turned by `angle` about the vertical axis through `centre` (a head turning; a test motion)."""
    c, s = np.cos(angle), np.sin(angle)
    p = np.asarray(points, np.float64) - centre
    return (np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1], p[..., 2]], axis=-1) + centre).astype(np.float32)


def bend(points, angle, pivot_height=1.0):
    """Points [..., 3] bent about the x axis by an angle growing from 0 at `pivot_height` to `angle`
    one unit below it (a neck bending: every strand rotates differently along its length; a test motion)."""
    p = np.asarray(points, np.float64)
    a = angle * np.clip(pivot_height - p[..., 2], 0.0, None)
    c, s = np.cos(a), np.sin(a)
    return np.stack([p[..., 0], c * p[..., 1] - s * p[..., 2], s * p[..., 1] + c * p[..., 2]], axis=-1).astype(np.float32)


def bench_animation(frames, asset=None, view="mid", width=128, spp=256, width_px=lod.DEFAULT_WIDTH_PX, guides=None,
                    params=None, seed=0, progress=None):
    """`frames`: the hair at successive frames (Strands, the same curves moved). `asset`: the LoD of the
    first frame (built here with `guides` guides when None); each frame's guides are read from its
    strands (lod.frame_guides). Returns a dict with the settings, one row per frame and the means.
    `progress(message)` is called before each frame when given."""
    if len(frames) < 2:
        raise ValueError(f"an animation needs at least 2 frames, got {len(frames)}")
    if int(spp) < 1 or int(width) < render.BLUR_BOX:
        raise ValueError(f"spp must be >= 1 and width >= {render.BLUR_BOX}, got spp={spp}, width={width}")
    if view not in render.VIEWS:
        raise ValueError(f"view must be one of {', '.join(render.VIEWS)}, got {view!r}")
    say = progress or (lambda message: None)
    build_seconds = None
    if asset is None:
        say("building the LoD of the first frame")
        start = time.perf_counter()
        asset = lod.build_lod(frames[0], guides=guides)
        build_seconds = time.perf_counter() - start
    frame_guides = [lod.frame_guides(asset, strands, f"frame {index}") for index, strands in enumerate(frames)]
    camera = render.frame_view(frames[0].points, view, width)
    rows, images = [], []
    for index, (strands, pose) in enumerate(zip(frames, frame_guides)):
        say(f"frame {index + 1} of {len(frames)}: every strand and the LoD at {spp} spp")
        strands_image = render.render(strands, "pt", width=width, spp=spp, params=params, seed=seed, camera=camera)
        lod_image = render.render(strands, "lod", width=width, spp=spp, asset=asset, params=params, seed=seed,
                                  camera=camera, width_px=width_px, guides=pose)
        rows.append({"frame": index, "strand_segments": int(strands_image["segments"]),
                     "lod_segments": int(lod_image["segments"]),
                     "strands_seconds": strands_image["seconds"], "lod_seconds": lod_image["seconds"]})
        images.append((strands_image["image"], lod_image["image"]))
    # PSNRs over the box the hair covers in any frame (a small far hair is not flattered by the empty
    # image around it), on whole blurring blocks.
    box = _hair_box([image for pair in images for image in pair], render.BLUR_BOX)
    crop = [(strands_image[box], lod_image[box]) for strands_image, lod_image in images]
    # An infinite PSNR (identical 8-bit images) is stored as None: strict JSON has no Infinity.
    for index, (row, (strands_image, lod_image)) in enumerate(zip(rows, crop)):
        row["lod_blurred_psnr"] = _finite(render.blurred_psnr(lod_image, strands_image))
        if index > 0:
            row["strands_adjacent_psnr"] = _finite(render.blurred_psnr(strands_image, crop[index - 1][0]))
            row["lod_adjacent_psnr"] = _finite(render.blurred_psnr(lod_image, crop[index - 1][1]))
    moving = rows[1:]

    def mean(key, rows=moving):
        """The mean over the frames whose PSNR is finite (None when there is none)."""
        values = [row[key] for row in rows if row[key] is not None]
        return float(np.mean(values)) if values else None

    gap = (mean("lod_adjacent_psnr") - mean("strands_adjacent_psnr")
           if mean("lod_adjacent_psnr") is not None and mean("strands_adjacent_psnr") is not None else None)

    return {"frames": len(frames), "strands": asset.strand_count, "guides": asset.guide_count, "view": view,
            "width": int(width), "spp": int(spp), "width_px": float(width_px), "build_seconds": build_seconds,
            "hair_box": [int(box[0].stop - box[0].start), int(box[1].stop - box[1].start)],
            "rows": rows, "mean_lod_blurred_psnr": mean("lod_blurred_psnr", rows),
            "mean_strands_adjacent_psnr": mean("strands_adjacent_psnr"), "mean_lod_adjacent_psnr": mean("lod_adjacent_psnr"),
            "adjacent_psnr_gap_db": gap,
            "mean_segment_reduction": float(np.mean([row["strand_segments"] / max(row["lod_segments"], 1) for row in rows]))}


def _finite(value):
    return float(value) if np.isfinite(value) else None


def _hair_box(images, block):
    """(row slice, column slice) of the pixels where any image's 8-bit sRGB differs from the first
    image's corner (the environment), grown to whole block x block blocks; the whole image if none."""
    background = render.to_srgb8(images[0][:1, :1])
    hair = np.zeros(images[0].shape[:2], bool)
    for image in images:
        hair |= np.any(render.to_srgb8(image) != background, axis=2)
    height, width = hair.shape
    if not hair.any():
        return slice(0, height - height % block), slice(0, width - width % block)
    rows, columns = np.flatnonzero(hair.any(axis=1)), np.flatnonzero(hair.any(axis=0))

    def span(first, last, size):
        usable = size - size % block
        start = min(first // block * block, usable - block)
        return slice(start, max(min(-(-(last + 1) // block) * block, usable), start + block))

    return span(rows[0], rows[-1], height), span(columns[0], columns[-1], width)
