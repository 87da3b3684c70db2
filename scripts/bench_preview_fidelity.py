"""Measures how close the viewport LoD preview looks to a converged path-traced image of the same view, in
a real Blender window (run under Xvfb).

Run: xvfb-run -a -s '-screen 0 1280x720x24' blender --factory-startup --python scripts/bench_preview_fidelity.py
     [-- --spp 256 --scale 0.25 --sun 3 --world 0.15 --out FILE.json]
For the bundled real hair (examples/data/tressfx/Ratboy_mohawk.tfx, stood upright from Y up) and 20,000
strands generated in examples/data/wavy_cap.hairmesh.json: builds the LoD, previews it lit by one sun
(irradiance 3) and a uniform grey world (0.15) under the Standard view transform, at a mid and a near
view (the viewport's camera set to hairlod.render.frame_view's), and path-traces the full strands
(hairlod.render, `pt`, --spp samples per pixel at --scale of the viewport's size) with the same camera,
sun, world and hair (the preview's, from the panel's defaults). The preview's hair radiance per pixel is
read from its hair layer (LodPreview.hair_pixels: the mean over the samples holding hair, which the
composite mixes with the viewport by their share); the screenshot, turned back into scene-linear
radiance through the screen's measured response (a ramp of written values drawn by a POST_VIEW
handler, as in tests/ui/test_view_transform.py) and unmixed from the viewport behind, checks on the
pixels every sample covers that the screen shows that radiance (screen_over_layer). The path-traced
hair's own radiance is unmixed from the sky in the pixels it covers partly (alpha from a coverage render
of the same camera rays). Reported per hair and view: the mean linear radiance per channel over the hair's pixels of
each image (both weighted by coverage) and their ratio, the luminance spread (5th-95th percentile) of each, and the
coverage ratio (the preview's hair pixels over the path-traced coverage summed over the image, both on
the viewport's pixel grid), with one JSON object printed at the end. The spread is also given on the
path-traced image's own pixels (spread_same_pixels, hairlod.render.same_pixels_spread: the preview
averaged onto them, the pixels both images cover, weighted by coverage), where the whole-image
spreads compare different pixels. The mean luminance on those pixels in six bands of rows, bottom to top
(rows_same_pixels, hairlod.render.same_pixels_rows), shows the hair's shading across the image: a
mohawk's roots against its tips. --strand-coverage off draws every strand a pixel wide (the panel's
Strand Coverage).

--hdri NAME lights both with an equirectangular image instead of the uniform world: one of Blender's
own studio-light worlds (datafiles/studiolights/world: city, courtyard, forest, interior, night,
studio, sunrise, sunset) or the path of an .exr / .hdr, times --hdri-strength. The preview fits it with
its SRBF lights (the panel's World: SRBF, the default); the path tracer looks the image up per ray
(Blender's equirectangular mapping), and the sky behind each path-traced pixel, which the unmixing takes
away, is the image along that pixel's camera ray.

--hairs Ratboy_mohawk or generated measures one of the two hairs.

The path-traced reference starts at --spp and doubles its samples (independent ones) until two doublings in
a row each move its luminance spread on the same pixels by at most --spread-tolerance of itself (default
2 %), or until --max-spp (default 4096): a sparse hair's reference is noisy where strands cover pixels
partly, and that noise widens its spread. Each view reports the spread at every doubling
(spread_series). --spread-tolerance 0 renders --spp once. --arrays also writes each view's images as .npz.

--max-bounces N limits the path tracer to N bounces after the first hit (0: direct light alone), to see
which orders of scattering between the strands the preview holds.
"""

import argparse
import json
import os
import sys
import time

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import window_steps  # noqa: E402  (scripts/window_steps.py)
from viewport_capture import RedrawTimes, render_camera  # noqa: E402  (scripts/viewport_capture.py)
sys.path.insert(0, os.path.join(REPO_ROOT, "tests", "ui"))
SUN_IRRADIANCE = 3.0
# The path-traced reference takes --spp samples, then twice as many at each step (independent ones, a new
# seed per batch) until two doublings in a row each move its luminance spread on the same pixels by at most
# this fraction of itself, or until MAX_SPP: the noise of a sparse hair's unmixed pixels widens the reference's
# spread (the preview's spread on the mohawk's near view read 0.72 / 0.77 / 0.80 of the reference's at 256 /
# 1024 / 4096 spp), a bias of the measurement, not of the preview.
SPREAD_TOLERANCE = 0.02
MAX_SPP = 4096
# The hairs measured, by the names --hairs takes: the bundled real one, and one generated in a hair mesh.
HAIRS = ("Ratboy_mohawk", "generated")
RAMP = np.linspace(0.0, 1.0, 33) ** 2.2  # written values, denser near black
DELAY = 1.0
QUIET = 1.0  # seconds without a redraw: the viewport is at rest
# The viewport's anti-aliasing while measuring (Preferences > Viewport > Anti-Aliasing), whose samples the
# preview's hair layer averages at rest: 32, so that the preview is measured for its bias. At Blender's
# default of 8 its own sampling noise (strands thinner than a pixel drawn on a sample by the probability of
# their width) widens its luminance spread: the mohawk's mid view read 1.32 of the converged reference's at 8
# samples and 0.93 at 32, lit by the sun alone, while its mean per band of the reference's brightness held
# (docs/preview.md, "The preview's own noise").
ANTI_ALIASING = "32"


def parse_args():
    parser = argparse.ArgumentParser()
    parser.add_argument("--spp", type=int, default=256,
                        help="the path-traced reference's samples per pixel, doubled until its spread settles")
    parser.add_argument("--spread-tolerance", type=float, default=SPREAD_TOLERANCE,
                        help=f"double the reference's samples until two doublings in a row each move its spread by "
                        f"at most this fraction of itself (default {SPREAD_TOLERANCE:g}; 0 renders --spp once)")
    parser.add_argument("--max-spp", type=int, default=MAX_SPP,
                        help=f"the most samples the reference doubles to (default {MAX_SPP})")
    parser.add_argument("--scale", type=float, default=0.25)
    parser.add_argument("--shadowing", type=float, help="the panel's Shadowing (default: the panel's default)")
    parser.add_argument("--views", default="mid,near")
    parser.add_argument("--world", type=float, default=0.15, help="the uniform world's colour (grey)")
    parser.add_argument("--sun", type=float, default=SUN_IRRADIANCE,
                        help=f"the sun's irradiance (default {SUN_IRRADIANCE:g}; 0 lights the hair by the world alone)")
    parser.add_argument("--sun-towards", type=lambda text: tuple(float(x) for x in text.split(",")),
                        help="the direction towards the sun, x,y,z in the hair's frame (Z up, the camera on -y; "
                        "default above the camera's left, as hairlod.render.default_lights)")
    parser.add_argument("--strand-coverage", choices=("on", "off"), default="on",
                        help="the preview's Strand Coverage (default on, the panel's default)")
    parser.add_argument("--cycles-samples", type=int, default=0,
                        help="also render the view with Cycles at this many samples (tests/blender/cycles_scene.py)")
    parser.add_argument("--hdri", help="light with this equirectangular image instead of the uniform world: a "
                        "studio-light world of Blender's (forest, city, ...) or a path")
    parser.add_argument("--hdri-strength", type=float, default=1.0, help="the image's strength (default 1)")
    parser.add_argument("--max-bounces", type=int, default=None,
                        help="the path tracer's bounces after the first hit (default: the renderer's, "
                        "every order that matters; 0 is direct light alone): which orders of scattering the "
                        "preview holds")
    parser.add_argument("--hairs", default=",".join(HAIRS),
                        help=f"which hairs, comma-separated (default all): {', '.join(HAIRS)}")
    parser.add_argument("--anti-aliasing", choices=("5", "8", "11", "16", "32"), default=ANTI_ALIASING,
                        help=f"the viewport's anti-aliasing samples while measuring (default {ANTI_ALIASING}: the "
                        "preview's bias; Blender's default 8 adds the noise an artist sees at rest)")
    parser.add_argument("--arrays", action="store_true",
                        help="also write each view's images as fidelity_<hair>_<view>[_<hdri>].npz beside the PNGs: the preview's "
                        "hair radiance and coverage, the path-traced hair's (unmixed from the sky) and its coverage")
    parser.add_argument("--out")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    unknown = [hair for hair in args.hairs.split(",") if hair not in HAIRS]
    if unknown:
        parser.error(f"--hairs: no hair named {', '.join(unknown)} ({', '.join(HAIRS)})")
    if args.spp < 1 or args.max_spp < args.spp:
        parser.error(f"--spp {args.spp} and --max-spp {args.max_spp}: need 1 <= spp <= max-spp")
    if not 0.0 <= args.spread_tolerance < 1.0:
        parser.error(f"--spread-tolerance {args.spread_tolerance:g}: need 0 <= tolerance < 1")
    if args.sun_towards is not None and (len(args.sun_towards) != 3 or not np.all(np.isfinite(args.sun_towards))
                                         or not np.linalg.norm(args.sun_towards) > 0.0):
        parser.error(f"--sun-towards {args.sun_towards}: need three finite numbers, not all 0")
    return args


def ramp_shader():
    interface = gpu.types.GPUStageInterfaceInfo("hairlod_fidelity_ramp")
    interface.smooth('VEC2', "v_uv")
    info = gpu.types.GPUShaderCreateInfo()
    info.vertex_in(0, 'VEC2', "position")
    info.vertex_out(interface)
    info.fragment_out(0, 'VEC4', "fragColor")
    info.vertex_source("void main() { v_uv = position * 0.5 + 0.5; gl_Position = vec4(position, 0.0, 1.0); }")
    values = ", ".join(f"{v:.8f}" for v in RAMP)
    info.fragment_source(f"const float ramp[{len(RAMP)}] = float[]({values});\n"
                         f"void main() {{ float v = ramp[min(int(v_uv.x * {len(RAMP)}.0), {len(RAMP) - 1})];"
                         " fragColor = vec4(v, v, v, 1.0); }")
    return gpu.shader.create_from_info(info)


def summary(linear, mask, weights=None):
    """Mean (weighted by `weights` when given) and 5th-95th percentile luminance of the hair's pixels."""
    from hairlod import render

    hair = linear[mask]
    lum = render.luminance(hair)
    mean = np.average(hair, axis=0, weights=None if weights is None else weights[mask])
    return {"mean": mean.tolist(), "pixels": int(mask.sum()),
            "spread": [float(np.percentile(lum, 5)), float(np.percentile(lum, 95))]}


def nested_step(scale):
    """Screen pixels per path-traced pixel a side (1 / --scale), None where the two grids do not nest."""
    step = int(round(1.0 / scale))
    return step if abs(step * scale - 1.0) <= 1e-6 else None


def rows_on_same_pixels(preview, mask, hair_radiance, alpha, scale):
    """hairlod.render.same_pixels_rows of the screenshot's hair against the path-traced hair, bottom to
    top of the screen (the arrays' rows run bottom-up), None as spread_on_same_pixels."""
    from hairlod import render

    step = nested_step(scale)
    rows = None if step is None else render.same_pixels_rows(preview, mask, hair_radiance, alpha, step)
    return None if rows is None else {"pixels": rows["pixels"], "preview": rows["image"], "path_traced": rows["reference"]}


def spread_on_same_pixels(preview, mask, hair_radiance, alpha, scale):
    """hairlod.render.same_pixels_spread of the screenshot's hair against the path-traced hair on the
    path-traced image's pixels (1 / scale screen pixels a side), None where the grids do not nest or
    too few pixels are covered by both."""
    from hairlod import render

    step = nested_step(scale)
    spread = None if step is None else render.same_pixels_spread(preview, mask, hair_radiance, alpha, step)
    return None if spread is None else {"pixels": spread["pixels"], "preview": spread["image"],
                                        "path_traced": spread["reference"], "ratio": spread["ratio"]}


def unmixed(image, alpha, background):
    """The hair's own radiance in pixels it covers partly: image = alpha hair + (1 - alpha) background
    (background: an RGB, or per pixel [H, W, 3])."""
    return (image - (1.0 - alpha[..., None]) * background) / np.maximum(alpha[..., None], 1e-6)


def hdri_path(name):
    """The file of --hdri: a path, or the name of one of Blender's studio-light worlds."""
    if os.path.isfile(name):
        return name
    folder = bpy.utils.system_resource('DATAFILES', path=os.path.join("studiolights", "world"))
    path = os.path.join(folder, name if name.endswith(".exr") else name + ".exr")
    if not os.path.isfile(path):
        known = sorted(f[:-4] for f in os.listdir(folder) if f.endswith(".exr")) if os.path.isdir(folder) else []
        raise SystemExit(f"--hdri: no file {name!r} and no studio-light world of that name (Blender has: "
                         f"{', '.join(known) or 'none'})")
    return path


def hdri_world(scene, path, strength):
    """Makes the scene's world the image at `path` (Environment Texture -> Background x strength) and
    returns its radiance as hairlod.render takes an environment: [H, W, 3] float32, top row up."""
    from hairlod.blender.versions import enable_nodes

    image = bpy.data.images.load(path, check_existing=True)
    world = scene.world
    enable_nodes(world)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    texture = nodes.get("hairlod HDRI") or nodes.new("ShaderNodeTexEnvironment")
    texture.name = "hairlod HDRI"
    texture.image = image
    background = nodes["Background"]
    links.new(texture.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = strength
    from hairlod.blender.preview.world_srbf import image_radiance

    # Blender's pixels run bottom-up; the renderer's rows top-down.
    return np.ascontiguousarray(image_radiance(image)[::-1].astype(np.float32) * strength)


def sky_behind(camera, environment):
    """The environment's radiance along each pixel's central camera ray ([H, W, 3], rows top-down), as
    hairlod.render's pinhole camera and Blender's equirectangular mapping give them."""
    eye, target, up = (np.asarray(camera[key], np.float64) for key in ("eye", "target", "up"))
    width, height = camera["width"], camera["height"]
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    upward = np.cross(right, forward)
    tan_half = np.tan(0.5 * camera["fov_y"])
    sx = (2.0 * (np.arange(width) + 0.5) / width - 1.0) * tan_half * width / height
    sy = (1.0 - 2.0 * (np.arange(height) + 0.5) / height) * tan_half
    rays = forward + sx[None, :, None] * right + sy[:, None, None] * upward
    rays /= np.linalg.norm(rays, axis=2, keepdims=True)
    rows, columns = environment.shape[:2]
    u = -np.arctan2(rays[..., 1], rays[..., 0]) / (2.0 * np.pi) + 0.5
    v = np.arctan2(rays[..., 2], np.hypot(rays[..., 0], rays[..., 1])) / np.pi + 0.5
    column = np.clip((u * columns).astype(int), 0, columns - 1)
    row = np.clip(((1.0 - v) * rows).astype(int), 0, rows - 1)
    return environment[row, column].astype(np.float64)


def cycles_image(strands, camera, sun_direction, samples, world, sun=SUN_IRRADIANCE):
    """The view rendered by Cycles (a headless Blender running tests/blender/cycles_scene.py) with the
    Principled Hair BSDF of the preview's default hair: linear RGB [H, W, 3], rows top-down."""
    import subprocess
    import tempfile

    import OpenImageIO as oiio

    from hairlod import io

    folder = tempfile.mkdtemp(prefix="hairlod-fidelity-")
    hair, scene, image = (os.path.join(folder, name) for name in ("hair.hair", "scene.json", "cycles.exr"))
    io.write(hair, strands)
    spec = {"addon": os.path.join(REPO_ROOT, "addon"), "hair": hair,
            "camera": {key: (list(map(float, value)) if isinstance(value, list) else value) for key, value in camera.items()},
            "sun": {"direction": list(map(float, sun_direction)), "irradiance": sun}, "world": world,
            "node": {"parametrization": "MELANIN", "melanin": 0.5, "melanin_redness": 0.3, "roughness": 0.3,
                     "radial_roughness": 0.3},
            "spp": samples, "seed": 5, "max_bounces": 70}
    with open(scene, "w", encoding="utf-8") as f:
        json.dump(spec, f)
    subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python",
                    os.path.join(REPO_ROOT, "tests", "blender", "cycles_scene.py"), "--", scene, image],
                   check=True, capture_output=True)
    source = oiio.ImageInput.open(image)
    pixels = source.read_image(format="float")[..., :3]
    source.close()
    return np.asarray(pixels, np.float64)


def steps(args):
    results = {}
    yield from measure(results, views=args.views.split(","), spp=args.spp, scale=args.scale, world=args.world,
                       sun_irradiance=args.sun,
                       strand_coverage=args.strand_coverage == "on", shadowing=args.shadowing,
                       cycles_samples=args.cycles_samples, hdri=args.hdri, hdri_strength=args.hdri_strength,
                       max_bounces=args.max_bounces, hairs=args.hairs.split(","),
                       spread_tolerance=args.spread_tolerance, max_spp=args.max_spp, arrays=args.arrays,
                       anti_aliasing=args.anti_aliasing, sun_towards=args.sun_towards)
    window_steps.report(results, args.out)


def measure(results, views=("mid", "near"), spp=256, scale=0.25, world=0.15, strand_coverage=True, shadowing=None,
            cycles_samples=0, sun_irradiance=SUN_IRRADIANCE, hdri=None, hdri_strength=1.0, max_bounces=None,
            hairs=HAIRS, spread_tolerance=SPREAD_TOLERANCE, max_spp=MAX_SPP, arrays=False, anti_aliasing=None,
            sun_towards=None):
    """The steps of the measurement (a generator for window_steps.run or tests/ui/harness.run), per hair
    and view, into `results` ({"<hair> <view>": entry}); arguments as the command line's (anti_aliasing None
    keeps the preferences' samples; sun_towards None puts the sun above the camera's left, as
    hairlod.render.default_lights). The preferences' anti-aliasing is restored afterwards."""
    import addon_utils

    from harness import screenshot

    os.makedirs(os.environ.get("HAIRLOD_UI_OUT", "out/ui"), exist_ok=True)
    addon_utils.enable("hairlod", default_set=True)
    import hairlod
    from hairlod import hairmesh, io, lod, render
    from hairlod.blender.versions import uses_nodes
    from hairlod.blender.preview import lod_preview
    from hairlod.blender.principled_hair import object_hair_params

    def image_name(name, view):
        """The images' names: fidelity_<hair>_<view>, then _<the HDRI's name> where one lights the scene (the
        UI test measures under three lightings into one folder)."""
        lighting = "" if hdri is None else "_" + os.path.splitext(os.path.basename(hdri))[0]
        return f"fidelity_{name.split()[0]}_{view}{lighting}"

    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    space, region_3d = area.spaces.active, area.spaces.active.region_3d
    space.overlay.show_overlays = False
    preferences = bpy.context.preferences.system
    anti_aliasing_before = preferences.viewport_aa
    if anti_aliasing is not None:
        preferences.viewport_aa = anti_aliasing
    space.show_gizmo = False
    space.show_region_toolbar = False
    space.show_region_header = False
    scene = bpy.context.scene
    scene.view_settings.view_transform = 'Standard'
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene.world.color = (world, world, world)
    if uses_nodes(scene.world):
        scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (world, world, world, 1.0)
        scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    environment = np.full(3, world, np.float32)
    if hdri is not None:
        if cycles_samples:
            raise SystemExit("--hdri: the Cycles comparison takes the uniform world only")
        environment = hdri_world(scene, hdri_path(hdri), hdri_strength)

    # The screen's response to written values (the framebuffer's encoding, as measured).
    program = ramp_shader()
    quad = batch_for_shader(program, 'TRI_STRIP', {"position": [(-1, -1), (1, -1), (-1, 1), (1, 1)]})

    def draw_ramp():
        program.bind()
        quad.draw(program)

    handle = bpy.types.SpaceView3D.draw_handler_add(draw_ramp, (), 'WINDOW', 'POST_VIEW')
    area.tag_redraw()
    yield DELAY
    shot = screenshot(window, area, "fidelity_response.png")
    bpy.types.SpaceView3D.draw_handler_remove(handle, 'WINDOW')
    y = int(region.y - area.y + 0.5 * region.height)
    xs = (region.x - area.x + (np.arange(len(RAMP)) + 0.5) / len(RAMP) * region.width).astype(int)
    response = shot[y, xs, 0]

    def to_linear(display):
        written = np.interp(display, response, RAMP)  # monotonic response: its inverse
        return written  # Standard: the preview writes srgb_decode(srgb_encode(x)) = x

    def mohawk():
        tfx = io.read(os.path.join(REPO_ROOT, "examples", "data", "tressfx", "Ratboy_mohawk.tfx"))
        upright = tfx.points @ np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float32).T  # Y up -> Z up
        return hairlod.Strands.from_counts(np.ascontiguousarray(upright), np.diff(tfx.offsets), tfx.radius)

    def generated():
        return hairlod.generate_strands(hairmesh.read(os.path.join(REPO_ROOT, "examples", "data", "wavy_cap.hairmesh.json")),
                                        count=20000, vertices=17, seed=1)

    # Only the hairs asked for (names of HAIRS, which parse_args checks) are read or generated.
    chosen = tuple(hairs)
    hairs = {name: make() for name, make in (("Ratboy_mohawk", mohawk), ("generated wavy 20k", generated))
             if any(name.startswith(hair) for hair in chosen)}
    redraws = RedrawTimes()
    try:
        for name, strands in hairs.items():
            asset = lod.build_lod(strands)
            holder = bpy.data.objects.new(name, None)
            scene.collection.objects.link(holder)
            lod_preview.attach(holder, asset)
            settings = holder.hairlod_lod_preview
            settings.use_material = False  # the panel's default hair: melanin 0.5, as the renderer's default
            settings.strand_coverage = strand_coverage
            if shadowing is not None:
                settings.self_shadowing = shadowing
            for view in views:
                camera = render.frame_view(strands.points, view, region.width, region.height)
                eye, target = np.array(camera["eye"]), np.array(camera["target"])
                region_3d.view_perspective = 'PERSP'
                region_3d.view_location = target
                region_3d.view_distance = float(np.linalg.norm(eye - target))
                forward = (target - eye) / np.linalg.norm(target - eye)
                from mathutils import Vector
                region_3d.view_rotation = Vector(-forward).to_track_quat('Z', 'Y')
                sun_direction = render.default_lights(camera)["directional"][0][0]
                if sun_towards is not None:
                    sun_direction = tuple(-np.asarray(sun_towards, np.float64) / np.linalg.norm(sun_towards))
                sun = bpy.data.objects.get("Sun") or bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
                if sun.name not in scene.collection.objects:
                    scene.collection.objects.link(sun)
                sun.data.energy = sun_irradiance
                sun.rotation_euler = Vector(-np.asarray(sun_direction)).to_track_quat('Z', 'Y').to_euler()
                settings.enabled = True
                area.tag_redraw()
                yield DELAY
                area.tag_redraw()
                yield DELAY
                # At rest, once the preview holds every sample of the viewport's anti-aliasing.
                yield from redraws.at_rest(QUIET)
                with_hair = screenshot(window, area, f"{image_name(name, view)}_preview.png")
                layer_colour, coverage, samples = lod_preview.preview_of(holder).hair_pixels(region_3d)
                settings.enabled = False
                area.tag_redraw()
                yield DELAY
                without = screenshot(window, area, f"{image_name(name, view)}_off.png")
                box = (slice(region.y - area.y, region.y - area.y + region.height),
                       slice(region.x - area.x, region.x - area.x + region.width))
                # The preview's own hair radiance: a pixel shows the mean over its samples that hold hair
                # (the layer's colour, which under Standard is the scene-linear radiance the screen shows),
                # mixed with what lies behind by the share of them that do (its coverage). It is read from
                # the layer, not unmixed from the screenshot: the viewport's 8-bit framebuffer rounds a
                # blend of dark hair over the grey behind it towards the grey (+0.24 of a step at 1 / 8
                # coverage, measured), which unmixing divides by the coverage: 1.19x the hair's radiance in
                # pixels one sample of 8 covers. The screenshot checks, on the pixels every sample covers,
                # that the screen shows the layer (screen_over_layer, 1 within the 8-bit steps).
                coverage = coverage[:region.height, :region.width]
                preview_linear = layer_colour[:region.height, :region.width]
                mask = coverage > 0.05
                whole = coverage > 0.999
                screen_linear = unmixed(to_linear(with_hair[box]), coverage, to_linear(without[box]))
                screen_over_layer = (screen_linear[whole].mean(axis=0) / np.maximum(preview_linear[whole].mean(axis=0), 1e-12)
                                     if whole.any() else None)
                # The viewport's projection, so that the path-traced camera sees what the viewport shows.
                traced_camera = render_camera(region, region_3d, target, scale)
                lights = {"directional": [(tuple(sun_direction), (sun_irradiance,) * 3)], "points": [],
                          "environment": environment}
                start = time.perf_counter()
                params = object_hair_params(holder)  # the hair the preview shades
                bounces = render.MAX_BOUNCES if max_bounces is None else max_bounces

                def reference(samples, seed):
                    """The path-traced image at `samples` spp and the coverage of the same camera rays (the renderer
                    draws sample s of a pixel from (seed, pixel, s)), so that unmixing leaves exactly the mean over
                    the samples that met hair; both flipped to the screenshot's rows (the render's run top-down)."""
                    image = render.render(strands, "pt", spp=samples, camera=traced_camera, lights=lights,
                                          params=params, seed=seed, max_bounces=bounces)["image"]
                    # With a coverage render of its own (64 spp, as before) the mohawk's sparse pixels, mostly a
                    # quarter covered, were divided by a share off by about a fifth of itself: the reference's
                    # luminance spread read 1.73x that with the same rays (256 spp, --scale 0.5, mid).
                    alpha = render.coverage(strands, "pt", spp=samples, camera=traced_camera, seed=seed)
                    return image[::-1], alpha[::-1]

                background = world if hdri is None else sky_behind(traced_camera, environment)[::-1]
                traced, alpha = reference(spp, 5)
                total, series = spp, []
                while True:
                    hair_radiance = unmixed(traced, alpha, background)  # the hair's own radiance, unmixed from the sky
                    spread = spread_on_same_pixels(preview_linear, coverage * mask, hair_radiance, alpha, scale)
                    width = None if spread is None else spread["path_traced"][1] - spread["path_traced"][0]
                    series.append({"spp": total, "path_traced_width": width,
                                   "spread_ratio": None if spread is None else spread["ratio"]})
                    # Settled when each of the last two doublings moved it by at most the tolerance: one small step
                    # alone can be the noise of the spread itself (the mohawk's mid view: -6.5 %, then +1.2 %).
                    widths = [step["path_traced_width"] for step in series[-3:]]
                    settled = len(widths) == 3 and None not in widths and \
                        all(abs(later - earlier) <= spread_tolerance * width
                            for earlier, later in zip(widths, widths[1:]))
                    if spread_tolerance <= 0.0 or width is None or settled or 2 * total > max_spp:
                        break
                    # As many samples again, independent of those so far (the next seed): the mean of the two.
                    more, more_alpha = reference(total, 5 + len(series))
                    traced, alpha, total = 0.5 * (traced + more), 0.5 * (alpha + more_alpha), 2 * total
                # Thin strands cover pixels partly (Ratboy's at a quarter size: a few over 0.5): the hair's pixels are
                # those it covers by more than 5 %, weighted by coverage, as the preview's above.
                covered = alpha > 0.05
                entry = {"preview": summary(preview_linear, mask, weights=coverage), "preview_samples": samples,
                         "screen_over_layer": None if screen_over_layer is None else screen_over_layer.tolist(),
                         "path_traced": summary(hair_radiance, covered, weights=alpha),
                         "render_seconds": time.perf_counter() - start, "spp": total, "max_bounces": bounces,
                         "segments": lod_preview.preview_of(holder).stats.get("segments")}
                entry["mean_ratio"] = (np.array(entry["preview"]["mean"]) / np.array(entry["path_traced"]["mean"])).tolist()
                entry["spread_same_pixels"] = spread
                entry["rows_same_pixels"] = rows_on_same_pixels(preview_linear, coverage * mask, hair_radiance, alpha, scale)
                entry["spread_series"] = series  # the reference's spread and the ratio at each doubling of its samples
                # How much of the image the hair covers: the preview's coverage against the path-traced
                # coverage, each summed over the image (the same pixel grid at --scale 1).
                entry["coverage_ratio"] = float(coverage[mask].sum() * scale ** 2 / max(float(alpha.sum()), 1e-9))
                if cycles_samples:
                    cycles = cycles_image(strands, traced_camera, sun_direction, cycles_samples, world,
                                          sun_irradiance)[::-1]
                    entry["cycles"] = summary(unmixed(cycles, alpha, world), covered, weights=alpha)
                    entry["cycles_ratio"] = (np.array(entry["preview"]["mean"]) / np.array(entry["cycles"]["mean"])).tolist()
                    entry["path_traced_over_cycles"] = (np.array(entry["path_traced"]["mean"]) /
                                                        np.array(entry["cycles"]["mean"])).tolist()
                results[f"{name} {view}"] = entry
                print(name, view, json.dumps({k: entry[k] for k in ("mean_ratio", "coverage_ratio", "spread_same_pixels",
                                                                   "rows_same_pixels", "spread_series")}),
                      "preview", entry["preview"],
                      "traced", entry["path_traced"], flush=True)
                out = os.path.join(os.environ.get("HAIRLOD_UI_OUT", "out/ui"), image_name(name, view))
                render.write_image(out + "_traced.png", traced[::-1])
                if arrays:  # rows bottom-up, as the screenshots'; the path-traced ones at --scale of the preview's size
                    np.savez_compressed(out + ".npz", preview=preview_linear, preview_coverage=coverage,
                                        path_traced=hair_radiance, path_traced_coverage=alpha)
            lod_preview.detach(holder.name)
            bpy.data.objects.remove(holder)
    finally:
        redraws.remove()
        preferences.viewport_aa = anti_aliasing_before


if __name__ == "__main__":
    window_steps.run(steps(parse_args()))
