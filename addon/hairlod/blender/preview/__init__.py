"""GPU drawing in the 3D viewport: draw handlers, batches and their GLSL shaders (shaders/*.glsl).

Nothing here draws in background mode (``blender -b``), where Blender has no GPU context: the draw
handlers are registered only when ``bpy.app.background`` is false.
"""
