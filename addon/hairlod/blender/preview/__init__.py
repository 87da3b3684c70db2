"""GPU drawing for viewport previews (draw handlers, batches, GLSL in shaders/).

Modules here import ``gpu`` inside functions only: the ``gpu`` module raises in background mode
(``blender -b``), where callers must not draw (check ``bpy.app.background``).
"""
