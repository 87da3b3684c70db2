"""The preview shows scene-linear radiance as Blender's colour management shows it (Blender under Xvfb,
see scripts/run_ui_tests.sh).

A POST_VIEW handler draws a row of patches whose scene-linear radiance runs from 0.001 to 8 through the
preview's own output path (shaders/view_transform.glsl with the table of
hairlod.blender.preview.view_transform); the screenshot of each patch must be the display value that
Blender's own colour management gives that radiance (Image.save_render of a float image holding it,
independent of the table), within 2/255, for Standard, Filmic and Filmic with exposure +1 and a look.
Before, the preview encoded to sRGB what the framebuffer encodes again (0.5 showed as 0.725 under
Standard instead of 0.735 for 0.5 linear, i.e. srgb(srgb(x)), and ignored Filmic). Screenshots go to
$HAIRLOD_UI_OUT (default out/ui).
"""

import os
import sys
import tempfile

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check, screenshot  # noqa: E402

RADIANCE = np.array([0.001, 0.004, 0.01, 0.02, 0.05, 0.1, 0.18, 0.3, 0.5, 0.8, 1.0, 2.0, 4.0, 8.0], np.float32)
# Per patch a colour: grey, and tinted so that the channels go through the table apart.
TINTS = np.array([[1.0, 1.0, 1.0], [1.0, 0.45, 0.12]], np.float32)
SETTINGS = (("Standard", "None", 0.0), ("Filmic", "None", 0.0), ("Filmic", "Medium High Contrast", 1.0))
TOLERANCE = 2.0 / 255.0
REDRAW_DELAY = 1.0

# The patches fill this part of the region (fractions of its width and height), clear of its edges.
PATCH_BOX = (0.1, 0.9, 0.2, 0.8)
VERTEX = f"""
void main()
{{
  v_uv = position * 0.5 + 0.5;
  gl_Position = vec4(mix({PATCH_BOX[0]}, {PATCH_BOX[1]}, v_uv.x) * 2.0 - 1.0,
                     mix({PATCH_BOX[2]}, {PATCH_BOX[3]}, v_uv.y) * 2.0 - 1.0, 0.0, 1.0);
}}
"""
FRAGMENT = """
void main()
{
  int index = min(int(v_uv.x * float(PATCHES)), PATCHES - 1);
  int row = v_uv.y < 0.5 ? 0 : 1;
  vec3 value = patches.levels[index].x * patches.tints[row].rgb;
  /* calibrate: written as it is, to measure what the framebuffer shows for a written value */
  fragColor = vec4(calibrate != 0 ? value : view_transform(value), 1.0);
}
"""


def patch_shader():
    from hairlod.blender.preview import view_transform
    from hairlod.blender.preview.shaders import glsl_source

    interface = gpu.types.GPUStageInterfaceInfo("hairlod_view_transform_test")
    interface.smooth('VEC2', "v_uv")
    info = gpu.types.GPUShaderCreateInfo()
    info.typedef_source(f"#define PATCHES {len(RADIANCE)}\n"
                        f"struct PatchBlock {{ vec4 levels[{len(RADIANCE)}]; vec4 tints[2]; }};\n")
    info.uniform_buf(0, "PatchBlock", "patches")
    info.push_constant('INT', "calibrate")
    info.vertex_in(0, 'VEC2', "position")
    info.vertex_out(interface)
    view_transform.declare(info)
    info.fragment_out(0, 'VEC4', "fragColor")
    info.vertex_source(VERTEX)
    info.fragment_source(view_transform.GLSL_CONSTANTS + glsl_source("view_transform.glsl") + FRAGMENT)
    return gpu.shader.create_from_info(info)


def reference(scene):
    """Display values [2, patches, 3] of the patches' radiance through Blender's colour management of
    `scene` (Image.save_render to a 16-bit PNG, no dither), read back as stored."""
    colours = RADIANCE[None, :, None] * TINTS[:, None, :]
    pixels = np.concatenate([colours, np.ones(colours.shape[:2] + (1,), np.float32)], axis=-1)
    image = bpy.data.images.new("patches", len(RADIANCE), 2, alpha=True, float_buffer=True)
    image.pixels.foreach_set(pixels.ravel())
    path = os.path.join(tempfile.mkdtemp(), "patches.png")
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = 'PNG', 'RGBA', '16'
    scene.render.dither_intensity = 0.0
    image.save_render(path, scene=scene)
    back = bpy.data.images.load(path)
    back.colorspace_settings.name = 'Non-Color'
    out = np.empty(len(RADIANCE) * 2 * 4, np.float32)
    back.pixels.foreach_get(out)
    bpy.data.images.remove(back)
    bpy.data.images.remove(image)
    return out.reshape(2, len(RADIANCE), 4)[..., :3]


def patch_block(levels, tints):
    block = np.zeros(4 * len(RADIANCE) + 8, np.float32)
    block[0:4 * len(RADIANCE):4] = levels
    block[4 * len(RADIANCE):].reshape(2, 4)[:, :3] = tints
    return gpu.types.GPUUniformBuf(gpu.types.Buffer('FLOAT', block.size, block))


def steps():
    from hairlod.blender.preview import lod_preview

    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    scene = bpy.context.scene
    space = area.spaces.active
    space.overlay.show_overlays = False  # no cursor, floor or text over the patches
    space.show_gizmo = False
    space.show_region_toolbar = False
    program = patch_shader()
    quad = batch_for_shader(program, 'TRI_STRIP', {"position": [(-1, -1), (1, -1), (-1, 1), (1, 1)]})
    # Calibration: written values spread over [0, 1] (denser near black), in both rows.
    written = np.linspace(0.0, 1.0, len(RADIANCE)) ** 2.2
    calibration = patch_block(written, np.ones((2, 3), np.float32))
    patches = patch_block(RADIANCE, TINTS)
    state = {"exact": False, "calibrate": 1}

    def draw():
        texture, state["exact"] = lod_preview._view_transforms.texture(bpy.context.scene, on_baked=area.tag_redraw)
        program.bind()
        program.uniform_block("patches", calibration if state["calibrate"] else patches)
        program.uniform_int("calibrate", state["calibrate"])
        program.uniform_sampler("view_lut", texture)
        quad.draw(program)

    def patch_values(shot):
        """The median of 5 x 5 pixels at each patch's centre [2, patches, 3] (rows bottom-up like window
        coordinates: tint 0 in the lower half of the box)."""
        left, right, bottom, top = PATCH_BOX
        fx = left + (right - left) * (np.arange(len(RADIANCE)) + 0.5) / len(RADIANCE)
        fy = bottom + (top - bottom) * np.array([0.25, 0.75])
        xs = (region.x - area.x + fx * region.width).astype(int)
        ys = (region.y - area.y + fy * region.height).astype(int)
        return np.array([[np.median(shot[y - 2:y + 3, x - 2:x + 3].reshape(-1, 3), axis=0) for x in xs] for y in ys])

    handle = bpy.types.SpaceView3D.draw_handler_add(draw, (), 'WINDOW', 'POST_VIEW')
    try:
        # What the viewport shows for what a POST_VIEW handler writes: the framebuffer encodes it for the
        # screen, by the sRGB curve on the specification's word, but Mesa's llvmpipe (Xvfb) follows a 2.2
        # power (0.0035 shows as 0.075, sRGB 0.045). Printed, and used as the screen's response below, so
        # that the test judges the preview's part: the value it writes.
        area.tag_redraw()
        yield REDRAW_DELAY
        response = patch_values(screenshot(window, area, "view_transform_response.png"))[0, :, 0]
        check(np.all(np.diff(response) >= -1.0 / 255.0) and response[-1] > 0.95,
              f"the framebuffer's response to written values is monotonic up to white {np.round(response, 3)}")
        srgb = np.where(written <= 0.0031308, 12.92 * written, 1.055 * written ** (1.0 / 2.4) - 0.055)
        print(f"framebuffer response: written {np.round(written, 4)}\n  shown {np.round(response, 3)}\n"
              f"  sRGB  {np.round(srgb, 3)}")
        state["calibrate"] = 0
        for view, look, exposure in SETTINGS:
            scene.view_settings.view_transform = view
            scene.view_settings.look = look
            scene.view_settings.exposure = exposure
            area.tag_redraw()
            yield REDRAW_DELAY
            for _ in range(10):  # the table is baked on a timer after the first draw
                if state["exact"]:
                    break
                area.tag_redraw()
                yield REDRAW_DELAY
            check(state["exact"], f"{view} / {look}: the scene's table was baked")
            name = f"view_transform_{view}_{look}_{exposure:g}.png".replace(" ", "_")
            shown = patch_values(screenshot(window, area, name))
            display = reference(scene)
            # The display value Blender's colour management gives each patch, decoded as the preview
            # writes it, through the screen's measured response.
            linear = np.where(display <= 0.04045, display / 12.92, ((display + 0.055) / 1.055) ** 2.4)
            # (interpolated against written^(1/2.2), where the response is nearly straight)
            expected = np.interp(linear ** (1.0 / 2.2), written ** (1.0 / 2.2), response)
            # Channels darker than 4/255 on display are left out: the viewport keeps what a handler writes in
            # an 8-bit sRGB buffer, which holds nothing between 0 and 0.5/255 (0.00015 linear).
            error = np.where(display >= 4.0 / 255.0, np.abs(shown - expected), 0.0)
            worst = np.unravel_index(np.argmax(error.max(axis=-1)), error.shape[:2])
            print(f"{view} / {look} / exposure {exposure:g}: shown {np.round(shown[worst], 3)} expected "
                  f"{np.round(expected[worst], 3)} (display {np.round(display[worst], 3)}) at radiance "
                  f"{RADIANCE[worst[1]]} tint {worst[0]}")
            check(error.max() <= TOLERANCE,
                  f"{view} / {look} / exposure {exposure:g}: every patch within {TOLERANCE * 255:.0f}/255 of Blender's "
                  f"colour management (largest {error.max() * 255:.1f}/255)")
    finally:
        bpy.types.SpaceView3D.draw_handler_remove(handle, 'WINDOW')


harness.run(steps)
