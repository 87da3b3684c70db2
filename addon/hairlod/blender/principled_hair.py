"""The Principled Hair BSDF of a Blender material as hairlod BCSDF parameters.

Inside Blender: ``params_from_material(material)`` (a HairParams) or ``principled_hair_inputs(material)``
(the node's inputs as a dict). As a script it serves ``python3 -m hairlod bake --from-blend``:

    blender -b --factory-startup FILE.blend --python principled_hair.py -- --material NAME

prints one line ``HAIRLOD_JSON {...}`` with the inputs, or ``HAIRLOD_ERROR <message>``.
"""
import json
import os
import sys

import bpy

try:
    from .versions import enable_nodes, uses_nodes
except ImportError:  # run as a script (above): no package around it
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from versions import enable_nodes, uses_nodes

NODE_TYPE = "ShaderNodeBsdfHairPrincipled"
JSON_MARKER = "HAIRLOD_JSON "
ERROR_MARKER = "HAIRLOD_ERROR "


def principled_hair_node(material):
    """The material's Principled Hair BSDF node (the one feeding the output when there are several);
    ValueError naming the material when it has none."""
    tree = material.node_tree if uses_nodes(material) else None
    nodes = [n for n in tree.nodes if n.bl_idname == NODE_TYPE] if tree else []
    if not nodes:
        raise ValueError(f"material '{material.name}' has no Principled Hair BSDF node")
    linked = [n for n in nodes if any(link.is_valid for socket in n.outputs for link in socket.links)]
    return (linked or nodes)[0]


# The node's sockets by identifier, which Blender keeps while labels change, where the snake-cased
# label is not from_principled_hair's name: Blender 4.0+ labels the Huang lobe multipliers Reflection,
# Transmission and Secondary Reflection over the identifiers 'R lobe', 'TT lobe', 'TRT lobe'.
_SOCKET_NAMES = {"R lobe": "reflection", "TT lobe": "transmission", "TRT lobe": "secondary_reflection"}


def socket_input_name(socket):
    """from_principled_hair's name of a Principled Hair BSDF socket, in every Blender version."""
    return _SOCKET_NAMES.get(getattr(socket, "identifier", ""), socket.name.lower().replace(" ", "_"))


def principled_hair_inputs(material):
    """The node's parametrization and model ('CHIANG' before Blender 4.0, which has no other) and every
    enabled input socket's value, in the snake-case names of ``hairlod.hair_params.from_principled_hair``
    (colours as RGB, Offset in radians). Blender enables the sockets of the node's model only (Radial
    Roughness and Coat for Chiang; Aspect Ratio, Reflection, Transmission, Secondary Reflection for
    Huang). Linked sockets (textures) contribute their unlinked default value."""
    node = principled_hair_node(material)
    inputs = {"parametrization": node.parametrization, "model": getattr(node, "model", "CHIANG")}
    for socket in node.inputs:
        if not socket.enabled or not hasattr(socket, "default_value"):
            continue
        value = socket.default_value
        inputs[socket_input_name(socket)] = [float(v) for v in value][:3] if hasattr(value, "__len__") else float(value)
    return inputs


def new_hair_material(name, inputs):
    """A new material whose surface is a Principled Hair BSDF set from `inputs`, in the names that
    principled_hair_inputs returns ("parametrization", then sockets in snake case: "melanin",
    "absorption_coefficient", ...; colours as RGB, Offset in radians); other inputs keep Blender's
    defaults. KeyError names an input the node does not have."""
    material = bpy.data.materials.new(name)
    enable_nodes(material)
    nodes = material.node_tree.nodes
    for node in list(nodes):
        nodes.remove(node)
    output = nodes.new("ShaderNodeOutputMaterial")
    node = nodes.new(NODE_TYPE)
    sockets = {socket_input_name(socket): socket for socket in node.inputs}
    for key, value in inputs.items():
        if key == "parametrization":
            node.parametrization = value
            continue
        if key == "model":
            if not hasattr(node, "model"):
                if value != "CHIANG":
                    bpy.data.materials.remove(material)
                    raise KeyError(f"the Principled Hair BSDF of Blender {bpy.app.version_string} has no model '{value}'")
                continue
            node.model = value
            continue
        if key not in sockets:
            bpy.data.materials.remove(material)
            raise KeyError(f"the Principled Hair BSDF has no input '{key}'")
        socket = sockets[key]
        if hasattr(value, "__len__"):  # colours have alpha, vectors (the absorption coefficient) do not
            value = (list(value) + [1.0])[:len(socket.default_value)]
        socket.default_value = value
    material.node_tree.links.new(node.outputs[0], output.inputs["Surface"])
    return material


def params_from_material(material):
    """hairlod HairParams of the material's Principled Hair BSDF (Chiang or Huang model)."""
    from ..hair_params import from_principled_hair

    return from_principled_hair(**principled_hair_inputs(material))


def material_params(obj):
    """HairParams of the Principled Hair BSDF of the first material of `obj` that has one, or None."""
    for slot in getattr(obj, "material_slots", ()):
        if slot.material is None:
            continue
        try:
            principled_hair_node(slot.material)
        except ValueError:
            continue
        return params_from_material(slot.material)
    return None


def object_hair_params(obj):
    """The hair `obj`'s LoD is previewed, baked and exported with, one for all three: the Principled Hair
    BSDF of its material when the LoD preview's Material is on and it has one, else the preview panel's
    melanin, redness and roughness (their defaults when the object was never shown in the panel)."""
    from ..hair_params import from_principled_hair

    settings = obj.hairlod_lod_preview
    if settings.use_material:
        params = material_params(obj)
        if params is not None:
            return params
    return from_principled_hair(parametrization='MELANIN', melanin=settings.melanin,
                                melanin_redness=settings.melanin_redness, roughness=settings.roughness,
                                radial_roughness=settings.radial_roughness)


def main(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) != 2 or args[0] != "--material":
        print(ERROR_MARKER + "usage: -- --material NAME", flush=True)
        return
    material = bpy.data.materials.get(args[1])
    if material is None:
        print(ERROR_MARKER + f"no material named '{args[1]}'", flush=True)
        return
    try:
        print(JSON_MARKER + json.dumps(principled_hair_inputs(material)), flush=True)
    except ValueError as error:
        print(ERROR_MARKER + str(error), flush=True)


if __name__ == "__main__":
    main(sys.argv)
