"""The add-on's pipeline as plain functions for `blender -b` scripts: build the LoD of a hair Curves
object, and export it (LoD folder with one .hair per level, and the BCSDF lookup tables baked for the
object's hair material and the asset's hair counts). The operators and examples/convert_blend_to_lod.py
call these."""

import os

import bpy
import numpy as np

from .curves import evaluated_curve_subset


def build_lod(obj, context=None, guides=None, levels=None, control_points=None, seed=None, scene_cameras_only=None,
              frame_step=None, width_px=None, level_objects=None):
    """Builds the LoD of the hair Curves object `obj` as the Build Hair LoD operator does (the asset
    packed into `obj`; with `level_objects`, one hidden, non-rendering Curves object per level in the
    "Hair LoD" collection) and returns the LodAsset. Like the operator, a parameter left None comes
    from the object's settings (the sidebar: obj.hairlod_lod_build, and the preview's width_px for
    the width threshold). Raises ValueError on bad input; leaves nothing half-made."""
    from .lod_build_job import LodBuildJob

    if obj is None or obj.type != 'CURVES':
        raise ValueError(f"'{getattr(obj, 'name', obj)}' is not a hair Curves object")
    settings = obj.hairlod_lod_build

    def given(value, name):
        return getattr(settings, name) if value is None else value

    job = LodBuildJob(context or bpy.context, obj, given(guides, "guides"), given(levels, "levels"),
                      given(control_points, "control_points"), given(seed, "seed"),
                      given(scene_cameras_only, "scene_cameras"), given(frame_step, "frame_step"),
                      obj.hairlod_lod_preview.width_px if width_px is None else width_px,
                      given(level_objects, "level_objects"))
    job.run()
    return job.asset


def guide_animation(obj, asset, frames, context=None, progress=None):
    """(frames, guides float32 [F, G, n_c, 3]): the guides of `obj`'s evaluated hair (armature,
    Deform Curves on Surface, Geometry Nodes, caches) at each of `frames`, read as the LoD preview
    reads them (only the guide curves, resampled as the build does). The scene is back at its frame
    afterwards. `progress(done, total)` is called after each frame. Raises ValueError when the hair's
    curves no longer match the asset at some frame."""
    context = context or bpy.context
    scene = context.scene
    frames = [int(frame) for frame in frames]
    current = scene.frame_current, scene.frame_subframe
    poses = []
    try:
        for done, frame in enumerate(frames, start=1):
            scene.frame_set(frame)
            depsgraph = context.evaluated_depsgraph_get()
            try:
                curves = evaluated_curve_subset(obj, asset.guide_strands, depsgraph, asset.strand_count)
            except ValueError as error:
                raise ValueError(f"frame {frame}: {error}") from None
            poses.append(asset.resample_guides(curves))
            if progress is not None:
                progress(done, len(frames))
    finally:
        scene.frame_set(current[0], subframe=current[1])
    return frames, np.stack(poses) if poses else np.empty((0, asset.guide_count, asset.control_points, 3), np.float32)


def export_lod(obj, directory, bake=True, theta_samples=64, hair_count_samples=64, frames=None, progress=None):
    """Writes the LoD asset packed into `obj` to `directory`: <directory>/lod (lod.save: manifest,
    arrays, one .hair of thick hairs per level) and, with `bake`, <directory>/bcsdf (bcsdf_bake.bake:
    OpenEXR tables + manifest) for the hair the LoD preview shows (principled_hair.object_hair_params:
    the object's Principled Hair BSDF, else the preview panel's hair), with
    hair counts up to the asset's largest crossing count. Each folder appears complete or not at all.
    `frames` (e.g. range(scene.frame_start, scene.frame_end + 1)): the guides of the animated hair at
    each frame are stored in the LoD folder (guide_animation; lod.load_animation reads them back),
    `progress(done, total)` called per frame. Returns a summary dict (paths, counts, the material used)."""
    from .. import atomic_output, bcsdf, bcsdf_bake, lod
    from .packed_asset import packed_asset

    asset = packed_asset(obj)
    if asset is None:
        raise ValueError(f"'{obj.name}' has no LoD asset: build it first (Build Hair LoD)")
    directory = os.path.abspath(bpy.path.abspath(os.fspath(directory)))
    lod_dir, bake_dir = os.path.join(directory, "lod"), os.path.join(directory, "bcsdf")
    # Both folders are checked before either is written, so a refusal leaves the export folder as it was.
    atomic_output.check_folder_target(lod_dir, lod.FORMAT_KIND, what=lod.WHAT)
    if bake:
        atomic_output.check_folder_target(bake_dir, bcsdf_bake.BAKE_FORMAT, what=bcsdf_bake.BAKE_WHAT)
    animation = guide_animation(obj, asset, frames, progress=progress) if frames is not None else None
    lod.save(asset, lod_dir, extra={"source_object": obj.name}, animation=animation)
    summary = {"object": obj.name, "strands": asset.strand_count, "levels": [len(l.n_total) for l in asset.levels],
               "lod": lod_dir, "frames": len(animation[0]) if animation is not None else 0}
    if bake:
        from .principled_hair import material_params, object_hair_params

        # The hair the preview shows: the material's when the preview uses it, else the panel's.
        from_material = obj.hairlod_lod_preview.use_material and material_params(obj) is not None
        crossed, _ = bcsdf.lod_hair_count_range(asset)
        bcsdf_bake.bake(object_hair_params(obj), bake_dir, theta_samples=theta_samples,
                   hair_count_samples=hair_count_samples, max_hair_count=max(crossed, 1.0 + 1e-6))
        summary.update(bcsdf=bake_dir, material="Principled Hair BSDF" if from_material else "LoD preview panel",
                       max_hair_count=crossed)
    return summary
