"""Live preview of the strands of a hair mesh while the artist edits it.

A ``depsgraph_update_post`` handler regenerates the Curves object "<name>_preview" of every hair
mesh whose Live Preview is on when its geometry, transform or strand settings change, with at most
PREVIEW_STRAND_LIMIT strands so that editing stays interactive.
"""

import bpy
from bpy.app.handlers import persistent

from .strand_settings import StrandSettings

PREVIEW_STRAND_LIMIT = 2000

# Per hair-mesh object name, the inputs of its current preview. Reading an edit-mode mesh tags it
# for an update, so without this the handler would regenerate again and again for one edit.
_preview_inputs = {}
# Building curves on Blender < 4.0 applies a modifier, which evaluates the depsgraph and calls the
# handler again in the middle of the write; those nested calls must do nothing.
_writing = False


def preview_name(obj):
    return f"{obj.name}_preview"


def refresh_preview(obj):
    """Regenerates the preview of ``obj`` if Live Preview is on and its inputs changed; removes
    the preview when Live Preview is off. An invalid hair mesh keeps the last preview."""
    settings = obj.hairlod_strands
    if not settings.live_preview:
        _preview_inputs.pop(obj.name, None)
        preview = bpy.data.objects.get(preview_name(obj))
        if preview is not None and preview.type == 'CURVES':
            curves = preview.data
            bpy.data.objects.remove(preview)
            if curves.users == 0:
                bpy.data.hair_curves.remove(curves)
        return

    from ..hairmesh import generate_strands
    from .curves import replace_generated_curves, rewrite_strand_data
    from .hair_mesh import hair_mesh_from_object

    try:
        hair_mesh = hair_mesh_from_object(obj)
    except ValueError:
        return  # mid-edit states are often invalid; the preview waits for a valid one
    inputs = (hair_mesh.layers.tobytes(), hair_mesh.face_vertices.tobytes(), hair_mesh.face_sizes.tobytes(),
              tuple(obj.matrix_world.col[i][j] for i in range(4) for j in range(4)),
              tuple(getattr(settings, key) for key in StrandSettings.__annotations__))
    # Undo can take the preview away without changing the inputs.
    preview = bpy.data.objects.get(preview_name(obj))
    if _preview_inputs.get(obj.name) == inputs and preview is not None:
        return
    global _writing
    _writing = True
    try:
        strands = generate_strands(hair_mesh, count=min(settings.count, PREVIEW_STRAND_LIMIT),
                                   vertices=int(settings.vertices), styling=settings.styling(), seed=settings.seed,
                                   lod=settings.lod, subdivision=settings.subdivision)
        # Rewriting in place keeps edits fast, and is the only way in edit mode before Blender 4.0.
        if preview is not None and preview.type == 'CURVES' and rewrite_strand_data(preview, strands):
            preview.matrix_world = obj.matrix_world
        else:
            collection = obj.users_collection[0] if obj.users_collection else bpy.context.scene.collection
            replace_generated_curves(obj, strands, preview_name(obj), collection)
    except (ValueError, RuntimeError) as error:
        print(f"hairlod: no preview for '{obj.name}': {error}")
        return
    finally:
        _writing = False
    _preview_inputs[obj.name] = inputs


@persistent
def update_previews(scene, depsgraph):
    if _writing:
        return
    from .hair_mesh import is_hair_mesh_object

    # Any update counts (settings edits tag the object too); refresh_preview skips unchanged inputs.
    changed = {update.id.original for update in depsgraph.updates if isinstance(update.id, bpy.types.Object)}
    for obj in changed:
        if is_hair_mesh_object(obj) and obj.hairlod_strands.live_preview:
            refresh_preview(obj)


def register_handler():
    bpy.app.handlers.depsgraph_update_post.append(update_previews)


def unregister_handler():
    bpy.app.handlers.depsgraph_update_post.remove(update_previews)
    _preview_inputs.clear()
