"""The LoD asset packed into a hair object: Build Hair LoD stores it in the object's custom property
PACKED_PROPERTY, so it is saved with the .blend; the viewport preview and Export Hair LoD read it back.
"""

from .. import lod

PACKED_PROPERTY = "hairlod_lod_asset"


def packed_asset(obj):
    """The LoD asset packed into `obj` by Build Hair LoD (None if it has none)."""
    data = obj.get(PACKED_PROPERTY)
    return None if data is None else lod.unpack(data, where=f"object {obj.name}: {PACKED_PROPERTY}")


def store_packed_asset(obj, asset):
    """Packs `asset` into `obj` (replacing what a previous build packed there)."""
    # Blender 4.3 cuts bytes assigned over an existing bytes property at their first NUL (a fresh
    # property keeps them whole), so the old one is removed first.
    if PACKED_PROPERTY in obj:
        del obj[PACKED_PROPERTY]
    obj[PACKED_PROPERTY] = lod.pack(asset)
