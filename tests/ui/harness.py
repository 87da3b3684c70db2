"""What every UI test (Blender under Xvfb, scripts/run_ui_tests.sh) shares: the repository on sys.path,
checks that print what they verified, and a runner that drives a test's steps from a timer so that
the window redraws between them, ending Blender with the test's status."""

import os
import subprocess
import sys
import tempfile
import traceback

import bpy
import numpy as np

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
OUT_DIR = os.environ.get("HAIRLOD_UI_OUT", os.path.join(REPO_ROOT, "out", "ui"))
HAIR_MESH = os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")  # the bundled hair mesh
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message)


def screenshot(window, area, name, whole_window=False):
    """Screenshot of `area` (or of the whole window) saved as OUT_DIR/name; RGB float [H, W, 3], rows
    bottom-up like window coordinates."""
    path = os.path.join(OUT_DIR, name)
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        if whole_window:
            bpy.ops.screen.screenshot(filepath=path, check_existing=False)
        else:
            bpy.ops.screen.screenshot_area(filepath=path, check_existing=False)
    pixels = _load_rgb(path)
    if not pixels.any():
        # Blender 4.3 under Xvfb (Debian 13's Mesa) reads its window back as black; the X server holds
        # what the window shows, so the picture is taken from there instead (and saved in its place).
        pixels = _x_display_pixels(window, None if whole_window else area)
        _save_rgb(pixels, path)
    return pixels


def generated_hair_object(count, vertices, seed, name="Hair"):
    """(strands, Curves object): the scene emptied of objects, then hair generated from the bundled
    wavy cap hair mesh as the object `name`, active and selected."""
    import hairlod
    from hairlod import hairmesh
    from hairlod.blender.curves import strands_to_curves

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    strands = hairlod.generate_strands(hairmesh.read(HAIR_MESH), count=count, vertices=vertices, seed=seed)
    obj = strands_to_curves(strands, name)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return strands, obj


def plain_view(area):
    """The 3D view `area` without the overlays that would draw over hair (floor, axes, cursor,
    selection outline, gizmos); returns (area, its RegionView3D)."""
    space = area.spaces.active
    space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
    space.overlay.show_cursor = space.overlay.show_outline_selected = False
    space.show_gizmo = False
    return area, space.region_3d


def background_then_preview(window, area, obj, name, delay):
    """A generator step (``background = yield from ...``): screenshots the view without `obj` as
    OUT_DIR/name, then shows `obj` with its LoD preview on; returns the background pixels."""
    obj.hide_set(True)
    area.tag_redraw()
    yield delay
    background = screenshot(window, area, name)
    obj.hide_set(False)
    obj.hairlod_lod_preview.enabled = True
    return background


def crop(pixels, window, region):
    """The pixels of `region` in a whole-window screenshot (which may be scaled from window to image size)."""
    scale_y, scale_x = pixels.shape[0] / window.height, pixels.shape[1] / window.width
    x0, y0 = int(region.x * scale_x), int(region.y * scale_y)
    x1, y1 = int((region.x + region.width) * scale_x), int((region.y + region.height) * scale_y)
    return pixels[y0:y1, x0:x1]


def _load_rgb(path):
    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[..., :3]


def _save_rgb(pixels, path):
    height, width = pixels.shape[:2]
    image = bpy.data.images.new("hairlod screenshot", width, height)
    rgba = np.ones((height, width, 4), np.float32)
    rgba[..., :3] = pixels
    image.pixels.foreach_set(rgba.ravel())
    image.filepath_raw, image.file_format = path, 'PNG'
    image.save()
    bpy.data.images.remove(image)


def _x_display_pixels(window, area):
    """The window (or the area's rectangle of it) as the X display shows it, captured with xwd: RGB float
    [H, W, 3] in [0, 1], rows bottom-up. Blender's window fills the Xvfb screen from its top-left corner
    (there is no window manager to move it)."""
    with tempfile.NamedTemporaryFile(suffix=".xwd") as capture:
        subprocess.run(["xwd", "-root", "-silent", "-out", capture.name], check=True)
        screen = read_xwd(capture.name)
    top = screen.shape[0] - window.height  # the window's bottom row is window y = 0
    pixels = screen[top:top + window.height, :window.width][::-1]
    if area is not None:
        pixels = pixels[area.y:area.y + area.height, area.x:area.x + area.width]
    return np.ascontiguousarray(pixels, np.float32) / 255.0


def read_xwd(path):
    """uint8 RGB [H, W, 3], rows top-down, of an X window dump of a TrueColor 24/32-bit screen (XWD
    version 7: a header of big-endian 32-bit fields, the window name, the colour map, then the rows)."""
    data = np.fromfile(path, np.uint8)
    header = data[:100].view(">u4")
    header_size, version, depth, width, height = (int(header[i]) for i in (0, 1, 3, 4, 5))
    byte_order, bits_per_pixel, bytes_per_line = int(header[7]), int(header[11]), int(header[12])
    red_mask, green_mask, blue_mask, colours = (int(header[i]) for i in (14, 15, 16, 19))
    if version != 7 or bits_per_pixel != 32 or depth != 24:
        raise ValueError(f"{path}: not a 24-bit TrueColor XWD (version {version}, depth {depth}, {bits_per_pixel} bpp)")
    start = header_size + 12 * colours
    rows = data[start:start + height * bytes_per_line].reshape(height, bytes_per_line)[:, :4 * width]
    words = rows.copy().view("<u4" if byte_order == 0 else ">u4").reshape(height, width)
    shifts = [(mask & -mask).bit_length() - 1 for mask in (red_mask, green_mask, blue_mask)]
    return np.stack([(words >> s) & 0xFF for s in shifts], axis=-1).astype(np.uint8)


def run(steps, first_delay=1.0):
    """Runs the generator `steps()` from a timer: each yielded number is the delay before the next
    step. Blender exits 0 when the steps end, 1 (with the traceback) when one raises. The timer is
    persistent, so steps may open another .blend."""
    os.makedirs(OUT_DIR, exist_ok=True)
    bpy.context.preferences.view.show_splash = False
    step = steps()

    def tick():
        try:
            return next(step)
        except StopIteration:
            finish(0)
        except Exception:
            traceback.print_exc()
            finish(1)
        return None

    bpy.app.timers.register(tick, first_interval=first_delay, persistent=True)


def finish(status):
    print("ui test:", "passed" if status == 0 else "FAILED")
    sys.stdout.flush()
    sys.stderr.flush()
    # quit_blender() always exits 0; the status must reach the runner.
    os._exit(status)
