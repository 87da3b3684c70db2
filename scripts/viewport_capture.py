"""What the viewport benchmarks under Xvfb share (scripts/bench_lod_preview.py,
scripts/bench_preview_animation.py, scripts/bench_preview_fidelity.py, scripts/bench_preview_latency.py
and the UI tests): the light and the viewport, timed redraws, the viewport coming to rest, screenshots
as arrays, a PSNR over the hair, and the viewport's camera for hairlod.render."""

import math
import time

import bpy
import numpy as np


def add_sun(scene):
    """The benchmarks' one light: a sun of irradiance 3 from above one side."""
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    sun.data.energy = 3.0
    sun.rotation_euler = (0.9, 0.3, 0.6)
    scene.collection.objects.link(sun)
    return sun


def bare_viewport(size):
    """(window, area, region, region_3d) of the first 3D viewport, without overlays or gizmos, its
    clipping range fitted to hair of `size` and a perspective view."""
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    space = area.spaces.active
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.clip_start, space.clip_end = 0.01 * size, 100.0 * size
    space.region_3d.view_perspective = 'PERSP'
    return window, area, region, space.region_3d


def psnr(a, b, background):
    """PSNR over the bounding box of the pixels where either image differs from the background, so
    that a small hair far away is not flattered by the empty viewport around it."""
    hair = (np.abs(a - background).max(axis=2) > 1 / 255) | (np.abs(b - background).max(axis=2) > 1 / 255)
    if not hair.any():
        return math.inf
    rows, columns = np.flatnonzero(hair.any(axis=1)), np.flatnonzero(hair.any(axis=0))
    box = (slice(rows[0], rows[-1] + 1), slice(columns[0], columns[-1] + 1))
    mse = float(np.mean((a[box] - b[box]) ** 2))
    return math.inf if mse == 0.0 else 10.0 * math.log10(1.0 / mse)


def capture(window, area, path):
    """Screenshot of `area` saved at `path`, as RGB float [H, W, 3] (rows bottom-up)."""
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.screen.screenshot_area(filepath=path, check_existing=False)
    image = bpy.data.images.load(path)
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)
    size = tuple(image.size)
    bpy.data.images.remove(image)
    return pixels.reshape(size[1], size[0], 4)[..., :3]


def _finish_drawing():
    from hairlod.blender.preview.lod_preview import gpu_finish  # the add-on's, once it is enabled

    gpu_finish()()


class RedrawTimes(list):
    """The times (time.perf_counter) at which the 3D viewports finished a redraw, appended by a
    POST_PIXEL handler from construction until remove()."""

    def __init__(self):
        super().__init__()
        self._handle = bpy.types.SpaceView3D.draw_handler_add(lambda: self.append(time.perf_counter()), (),
                                                              'WINDOW', 'POST_PIXEL')

    def remove(self):
        if self._handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self._handle, 'WINDOW')
            self._handle = None

    def at_rest(self, quiet, longest=90.0, poll=0.05):
        """A step generator (``yield from``, its yields the seconds to wait): returns once no redraw has
        ended for `quiet` seconds, counted from the call at the earliest (a change made just before is
        redrawn only once the steps yield), or after `longest` seconds. After a change Blender redraws
        a viewport at rest once per sample of its anti-aliasing (8 by default): `quiet` must be longer
        than one redraw."""
        start = time.perf_counter()
        while time.perf_counter() - start < longest:
            if time.perf_counter() - max(self[-1] if self else start, start) >= quiet:
                return
            yield poll


def redraw(window, area, region, iterations=1, finish=False, before=None):
    """Seconds per redraw of `region`, over `iterations` redraws. With `finish`, each redraw ends by
    reading a pixel back in a POST_PIXEL handler, so that the time holds the GPU's work on it: without,
    a software GPU (llvmpipe) may still be drawing when the call returns, and whatever runs next (a
    screenshot, the next frame) pays for the rest. `before`, when given, is called before each redraw,
    untimed (a preview's draw_again, so that an unchanged view is drawn in full)."""
    handle = bpy.types.SpaceView3D.draw_handler_add(_finish_drawing, (), 'WINDOW', 'POST_PIXEL') if finish else None
    try:
        with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
            if before is None:
                start = time.perf_counter()
                bpy.ops.wm.redraw_timer(type='DRAW', iterations=iterations)
                seconds = time.perf_counter() - start
            else:
                seconds = 0.0
                for _ in range(iterations):
                    before()
                    start = time.perf_counter()
                    bpy.ops.wm.redraw_timer(type='DRAW', iterations=1)
                    seconds += time.perf_counter() - start
    finally:
        if handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(handle, 'WINDOW')
    return seconds / iterations


def render_camera(region, region_3d, target, scale=1.0):
    """hairlod.render's camera for what a perspective viewport shows (its projection and view; `target`
    the point it looks at), at `scale` times the region's pixels."""
    from mathutils import Vector

    projection = np.array(region_3d.window_matrix)
    up = np.array(region_3d.view_rotation @ Vector((0.0, 1.0, 0.0)))
    return {"eye": list(np.array(region_3d.view_matrix.inverted().translation)), "target": list(target),
            "up": list(up), "fov_y": float(2.0 * np.arctan(1.0 / projection[1, 1])),
            "width": max(8, round(region.width * scale)), "height": max(8, round(region.height * scale))}
