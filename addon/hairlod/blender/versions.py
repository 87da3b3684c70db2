"""What differs between the Blender releases the add-on runs in (3.4 to 5.x), kept in one place."""

import bpy

# Blender 5 always shades materials and worlds with their node trees: `use_nodes` is deprecated there
# (to be removed in 6.0, a DeprecationWarning on every use) and reads True.
ALWAYS_NODES = bpy.app.version >= (5, 0, 0)


def uses_nodes(data):
    """Whether a material or world is shaded by its node tree."""
    return data.node_tree is not None and (ALWAYS_NODES or data.use_nodes)


def enable_nodes(data):
    """Has a material or world shaded by its node tree (which Blender then makes, where missing)."""
    if not ALWAYS_NODES:
        data.use_nodes = True
