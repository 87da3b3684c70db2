"""hairlod.blender.principled_hair: a material's Principled Hair BSDF as BCSDF parameters, headless."""

import math

import bpy
import pytest

from hairlod import hair_params
from hairlod.blender.principled_hair import params_from_material, principled_hair_inputs
from hairlod.blender.versions import enable_nodes


@pytest.fixture
def hair_material():
    material = bpy.data.materials.new("HairParamsTest")
    enable_nodes(material)
    nodes = material.node_tree.nodes
    node = nodes.new("ShaderNodeBsdfHairPrincipled")
    node.parametrization = "ABSORPTION"
    node.inputs["Absorption Coefficient"].default_value = (0.3, 0.6, 1.4)
    node.inputs["Roughness"].default_value = 0.35
    node.inputs["Radial Roughness"].default_value = 0.5
    node.inputs["IOR"].default_value = 1.5
    node.inputs["Offset"].default_value = math.radians(-2.0)
    material.node_tree.links.new(node.outputs[0], nodes["Material Output"].inputs["Surface"])
    yield material
    bpy.data.materials.remove(material)


def test_params_from_material_follow_the_node(hair_material):
    inputs = principled_hair_inputs(hair_material)
    assert inputs["parametrization"] == "ABSORPTION"
    assert inputs["absorption_coefficient"] == pytest.approx([0.3, 0.6, 1.4])
    params = hair_params.params_to_dict(params_from_material(hair_material))
    assert params["sigma_a"] == pytest.approx([0.3, 0.6, 1.4])
    assert params["eta"] == pytest.approx(1.5) and params["alpha"] == pytest.approx(math.radians(-2.0))
    assert params["beta_m"] == pytest.approx(0.35) and params["beta_n"] == pytest.approx(0.5)


def test_material_without_the_node_is_named():
    plain = bpy.data.materials.new("PlainTest")
    enable_nodes(plain)
    with pytest.raises(ValueError, match="material 'PlainTest' has no Principled Hair BSDF node"):
        params_from_material(plain)
    bpy.data.materials.remove(plain)


def test_new_hair_material_sets_the_inputs_principled_hair_inputs_reads():
    from hairlod.blender.principled_hair import new_hair_material

    wanted = {"parametrization": "MELANIN", "melanin": 0.7, "melanin_redness": 0.2, "tint": [0.9, 0.8, 0.7],
              "roughness": 0.25, "offset": math.radians(3.0)}
    material = new_hair_material("Written", wanted)
    try:
        inputs = principled_hair_inputs(material)
        assert inputs["parametrization"] == "MELANIN"
        for key, value in wanted.items():
            if key != "parametrization":
                assert inputs[key] == pytest.approx(value, rel=1e-6), key
    finally:
        bpy.data.materials.remove(material)
    materials = len(bpy.data.materials)
    with pytest.raises(KeyError, match="no input 'shine'"):
        new_hair_material("Bad", {"shine": 1.0})
    assert len(bpy.data.materials) == materials  # nothing left behind


@pytest.mark.skipif(bpy.app.version < (4, 0, 0), reason="Blender before 4.0 has no Huang hair model")
def test_huang_mode_is_read_with_its_own_sockets():
    # Blender 4.x: the lobe multipliers are read by their socket identifiers (labels Reflection,
    # Transmission, Secondary Reflection); the Chiang-only sockets are disabled and not read.
    from hairlod.blender.principled_hair import new_hair_material

    material = new_hair_material("HuangTest", {"model": "HUANG", "parametrization": "MELANIN", "melanin": 0.4,
                                               "aspect_ratio": 0.7, "reflection": 0.5, "transmission": 0.25,
                                               "secondary_reflection": 2.0, "roughness": 0.2})
    try:
        inputs = principled_hair_inputs(material)
        assert inputs["model"] == "HUANG"
        assert "radial_roughness" not in inputs and "coat" not in inputs
        assert (inputs["reflection"], inputs["transmission"], inputs["secondary_reflection"]) == pytest.approx((0.5, 0.25, 2.0))
        params = params_from_material(material)
        assert params.fibre == "huang"
        assert (params.aspect_ratio, params.weight_r, params.weight_tt, params.weight_trt) == pytest.approx((0.7, 0.5, 0.25, 2.0))
        assert params.microfacet_roughness == pytest.approx(0.2)
    finally:
        bpy.data.materials.remove(material)


def test_chiang_is_the_model_blender_reads_before_huang_existed(hair_material):
    from hairlod.blender.principled_hair import new_hair_material

    assert principled_hair_inputs(hair_material)["model"] == "CHIANG"
    if bpy.app.version < (4, 0, 0):
        materials = len(bpy.data.materials)
        with pytest.raises(KeyError, match="no model 'HUANG'"):
            new_hair_material("Huang", {"model": "HUANG"})
        assert len(bpy.data.materials) == materials
