"""Drives a benchmark's steps in a real Blender window: a generator whose yields are the seconds to wait
before its next step runs from a timer, so that the window redraws between steps. Blender exits 0 when
the steps end and 1, with the traceback, when one raises."""

import json
import os
import traceback

import bpy


def run(steps, first_delay=1.0):
    """Starts the generator `steps` (already created) on a timer."""
    bpy.context.preferences.view.show_splash = False

    def tick():
        try:
            return next(steps)
        except StopIteration:
            os._exit(0)
        except Exception:
            traceback.print_exc()
            os._exit(1)
        return None

    bpy.app.timers.register(tick, first_interval=first_delay)


def run_once(function, first_delay=1.0):
    """Runs `function()` once from a timer (the window is up by then), then exits as run() does."""
    def steps():
        function()
        yield from ()

    run(steps(), first_delay)


def report(result, path=None):
    """Prints `result` as one indented JSON object, and writes it to `path` when given."""
    text = json.dumps(result, indent=1)
    print(text)
    if path:
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
