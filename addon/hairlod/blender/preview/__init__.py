"""GPU drawing in the 3D viewport: draw handlers and their GLSL shaders (shaders/*.glsl)."""
