"""What every UI test (Blender under Xvfb, scripts/run_ui_tests.sh) shares: the repository on sys.path,
checks that print what they verified, and a runner that drives a test's steps from a timer so that
the window redraws between them, ending Blender with the test's status."""

import os
import sys
import traceback

import bpy
import numpy as np

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
OUT_DIR = os.environ.get("HAIRLOD_UI_OUT", os.path.join(REPO_ROOT, "out", "ui"))
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
    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[..., :3]


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
