"""Runs pytest inside Blender's Python (Debian's Blender uses the system Python, which has pytest).

blender -b --factory-startup --python-exit-code 1 --python tests/blender/pytest_main.py -- [pytest args]
"""

import sys

import pytest

pytest_args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
# Blender quits with this status; SystemExit is how a --python script sets it.
sys.exit(pytest.main(["-p", "no:cacheprovider", *pytest_args]))
