"""The scene's colour management (view transform, look, exposure, gamma, display device) as a 3D lookup
table that the preview's fragment shaders apply to their scene-linear radiance (shaders/view_transform.glsl),
so that the preview shows what a render of the scene shows under the same settings.

Blender exposes no colour-management call to Python, but Image.save_render() writes an image through
the view transform of a scene: a float image holding the table's lattice of inputs is saved as a 16-bit
PNG through a scratch scene that copies the user's settings, and read back as display values. The
viewport's framebuffer encodes what a POST_VIEW handler writes with the sRGB transfer curve, so the
shader writes the sRGB decoding of the display value it wants to see.

Data may not be created while Blender draws: ``ViewTransforms.texture(scene)`` returns the table of the
scene's current settings when it is baked, else the analytic Standard transform (sRGB, no look) of the
same exposure and gamma, and schedules the bake on a timer that redraws the viewports when done.
"""

import os
import tempfile

import bpy
import gpu
import numpy as np

LUT_SIZE = 33  # lattice points per axis
# Shaper from scene-linear x >= 0 to the table's coordinate u in [0, 1]: logarithmic above SHAPER_LOW,
# linear below it, saturating at SHAPER_HIGH (16 stops; Filmic and AgX reach white near 16).
SHAPER_LOW = 2.0 ** -10
SHAPER_HIGH = 2.0 ** 6
SAMPLER_SLOT = 7  # of "view_lut" (the BCSDF tables take 0-2, the world's 3, the selection 6)


# Prepended to shaders that include shaders/view_transform.glsl.
GLSL_CONSTANTS = f"#define VIEW_SHAPER_LOW {SHAPER_LOW!r}\n#define VIEW_SHAPER_HIGH {SHAPER_HIGH!r}\n"


def declare(info, slot=SAMPLER_SLOT):
    """Declares view_transform.glsl's table on a GPUShaderCreateInfo."""
    info.sampler(slot, 'FLOAT_3D', "view_lut")


def shaper(x):
    """The table coordinate u in [0, 1] of scene-linear values x (the inverse of lattice())."""
    x = np.clip(np.asarray(x, np.float64), 0.0, SHAPER_HIGH)
    return np.log2(1.0 + x / SHAPER_LOW) / np.log2(1.0 + SHAPER_HIGH / SHAPER_LOW)


def lattice(size=LUT_SIZE):
    """The scene-linear value of each of the table's `size` points per axis."""
    u = np.linspace(0.0, 1.0, size)
    return SHAPER_LOW * (np.exp2(u * np.log2(1.0 + SHAPER_HIGH / SHAPER_LOW)) - 1.0)


def srgb_encode(linear):
    linear = np.clip(np.asarray(linear, np.float64), 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1.0 / 2.4) - 0.055)


def settings_key(scene):
    """What the table depends on: the scene's view and display settings."""
    view, display = scene.view_settings, scene.display_settings
    return (display.display_device, view.view_transform, view.look, round(float(view.exposure), 6),
            round(float(view.gamma), 6), bool(view.use_curve_mapping))


def standard_table(exposure=0.0, gamma=1.0, size=LUT_SIZE):
    """Display values [size, size, size, 4] (index order b, g, r as a 3D texture reads them) of the
    Standard view transform on an sRGB display: sRGB encoding of x 2^exposure, then the display gamma."""
    values = srgb_encode(lattice(size) * 2.0 ** exposure) ** (1.0 / max(gamma, 1e-3))
    table = np.ones((size, size, size, 4), np.float32)
    table[..., 0] = values[None, None, :]
    table[..., 1] = values[None, :, None]
    table[..., 2] = values[:, None, None]
    return table


def bake_table(scene, size=LUT_SIZE):
    """Display values [size, size, size, 4] (b, g, r index order) of `scene`'s colour management, through
    Image.save_render. Not while Blender draws (it creates data)."""
    values = lattice(size).astype(np.float32)
    # One row per (b, g) pair, r along the row: an image size^2 x size... laid out size x size^2.
    r = np.tile(values, size * size)
    g = np.tile(np.repeat(values, size), size)
    b = np.repeat(values, size * size)
    pixels = np.stack([r, g, b, np.ones_like(r)], axis=-1).astype(np.float32)
    width, height = size, size * size
    image = bpy.data.images.new("hairlod view transform lattice", width, height, alpha=True, float_buffer=True)
    scratch = bpy.data.scenes.new("hairlod view transform")
    folder = tempfile.mkdtemp(prefix="hairlod-view-")
    path = os.path.join(folder, "lattice.png")
    readback = None
    try:
        image.pixels.foreach_set(pixels.ravel())
        view, source = scratch.view_settings, scene.view_settings
        scratch.display_settings.display_device = scene.display_settings.display_device
        view.view_transform = source.view_transform
        view.look = source.look
        view.exposure = source.exposure
        view.gamma = source.gamma
        view.use_curve_mapping = False  # curves are not copied (documented: the table ignores them)
        settings = scratch.render.image_settings
        settings.file_format = 'PNG'
        settings.color_mode = 'RGBA'
        settings.color_depth = '16'
        scratch.render.dither_intensity = 0.0
        image.save_render(path, scene=scratch)
        readback = bpy.data.images.load(path)
        readback.colorspace_settings.name = 'Non-Color'  # the stored display values, not linearised
        out = np.empty(width * height * 4, np.float32)
        readback.pixels.foreach_get(out)
    finally:
        for block, collection in ((readback, bpy.data.images), (image, bpy.data.images), (scratch, bpy.data.scenes)):
            if block is not None:
                collection.remove(block)
        if os.path.exists(path):
            os.remove(path)
        os.rmdir(folder)
    # Image rows run bottom-up from pixel (0, 0): row index = b * size + g, column = r.
    table = out.reshape(size, size, size, 4).copy()
    table[..., 3] = 1.0
    return table


def texture_of(table):
    """A 3D RGBA16F GPUTexture of a table [size, size, size, 4]."""
    size = table.shape[0]
    data = gpu.types.Buffer('FLOAT', table.size, np.ascontiguousarray(table, np.float32).ravel())
    return gpu.types.GPUTexture((size, size, size), format='RGBA16F', data=data)


class ViewTransforms:
    """The table of each set of settings met, uploaded once; baked on a timer when first asked for."""

    def __init__(self):
        self._textures = {}
        self._pending = None

    def texture(self, scene, on_baked=None):
        """(GPUTexture, exact): the scene's table, or (while it is baked) Standard's with its exposure and
        gamma. `on_baked()` is called after a bake (to redraw)."""
        key = settings_key(scene)
        if key in self._textures:
            return self._textures[key], True
        if key[1] == 'Standard' and key[2] == 'None' and key[0] == 'sRGB' and not key[5]:
            self._textures[key] = texture_of(standard_table(key[3], key[4]))
            return self._textures[key], True
        if self._pending is None:
            self._pending = key
            scene_name = scene.name

            def bake():
                self._pending = None
                target = bpy.data.scenes.get(scene_name)
                if target is not None and settings_key(target) == key:
                    self._textures[key] = texture_of(bake_table(target))
                    if on_baked is not None:
                        on_baked()
                return None

            bpy.app.timers.register(bake, first_interval=0.0)
        fallback = ('sRGB', 'Standard', 'None', key[3], key[4], False)
        if fallback not in self._textures:
            self._textures[fallback] = texture_of(standard_table(key[3], key[4]))
        return self._textures[fallback], False
