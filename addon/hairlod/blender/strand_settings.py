"""The strand generator's settings as Blender properties (StrandSettings), declared once for the
Generate Strands operator and for the settings each hair-mesh object keeps (hair_mesh_settings.py).
Both strand previews read them too, so they live below the operators and the previews."""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty

# Strand vertex counts the generator accepts: 2^e + 1 (and 2, a straight segment).
_VERTEX_COUNTS = (2, 3, 5, 9, 17, 33, 65, 129)


def _tag_owner(settings, context):
    # Tagging the hair-mesh object that holds the settings lets the live preview handler see the change.
    if isinstance(settings.id_data, bpy.types.Object):
        settings.id_data.update_tag()


class StrandSettings:
    """Strand generation settings: the Generate Strands operator's properties, also kept on each
    hair-mesh object (``Object.hairlod_strands``) so that the sidebar shows and edits them."""

    count: IntProperty(
        name="Strands",
        description="Number of strands at full level of detail",
        default=10000,
        min=1,
        soft_max=200000,
        update=_tag_owner,
    )
    vertices: EnumProperty(
        name="Vertices",
        description="Vertices per strand at full level of detail",
        items=[(str(count), str(count), f"{count} vertices per strand") for count in _VERTEX_COUNTS],
        default="17",
        update=_tag_owner,
    )
    seed: IntProperty(
        name="Seed",
        description="Seed of every random choice (roots, per-strand styling)",
        default=0,
        min=0,
        update=_tag_owner,
    )
    subdivision: IntProperty(
        name="Subdivision",
        description="Smooth refinement level of the hair mesh before growing strands",
        default=0,
        min=0,
        max=3,
        update=_tag_owner,
    )
    lod: FloatProperty(
        name="Level of Detail",
        description="Fraction of the strands and vertices kept (1: all)",
        default=1.0,
        min=0.001,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )
    curl_radius: FloatProperty(
        name="Curl Radius",
        description="Radius of the curl helix (0: no curl)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    curl_frequency: FloatProperty(
        name="Curl Frequency",
        description="Curl turns per unit of strand length",
        default=10.0,
        min=0.0,
        update=_tag_owner,
    )
    wave_amplitude: FloatProperty(
        name="Wave Amplitude",
        description="Amplitude of the planar wave (0: no wave)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    wave_frequency: FloatProperty(
        name="Wave Frequency",
        description="Wave periods per unit of strand length",
        default=3.0,
        min=0.0,
        update=_tag_owner,
    )
    clump_amount: FloatProperty(
        name="Clump",
        description="Pull of the tips towards their bundle's centre (0: no clumping)",
        default=0.0,
        min=0.0,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )
    frizz_amplitude: FloatProperty(
        name="Frizz",
        description="Amplitude of the per-strand noise (0: no frizz)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    frizz_frequency: FloatProperty(
        name="Frizz Frequency",
        description="Frizz noise cells per unit of strand length",
        default=20.0,
        min=0.0,
        update=_tag_owner,
    )
    trim_amount: FloatProperty(
        name="Trim",
        description="Random shortening: each strand keeps between 1 - trim and all of its length (0: no trim)",
        default=0.0,
        min=0.0,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )

    def copy_settings(self, source):
        for key in StrandSettings.__annotations__:
            setattr(self, key, getattr(source, key))

    def styling(self):
        """The styling operations whose amount is not zero, in a fixed order."""
        from ..hairmesh import Clump, Curl, Frizz, Trim, Wave

        operations = []
        if self.curl_radius > 0:
            operations.append(Curl(radius=self.curl_radius, frequency=self.curl_frequency))
        if self.wave_amplitude > 0:
            operations.append(Wave(amplitude=self.wave_amplitude, frequency=self.wave_frequency))
        if self.clump_amount > 0:
            operations.append(Clump(amount=self.clump_amount))
        if self.frizz_amplitude > 0:
            operations.append(Frizz(amplitude=self.frizz_amplitude, frequency=self.frizz_frequency))
        if self.trim_amount > 0:
            operations.append(Trim(amount=self.trim_amount))
        return operations
