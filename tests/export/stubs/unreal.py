"""A stand-in for Unreal Editor's `unreal` module, for tests/export/engines.rs: it records
what docs/engines/unreal/windloom_import.py asks of the editor. Enum values and properties
are limited to those Unreal's Python API documents, so a misspelt name fails here as it
would in Unreal."""

import os

calls = []

_ENUMS = {
    "TextureCompressionSettings": {
        "TC_DEFAULT", "TC_NORMALMAP", "TC_MASKS", "TC_GRAYSCALE", "TC_DISPLACEMENTMAP",
        "TC_VECTOR_DISPLACEMENTMAP", "TC_HDR", "TC_EDITOR_ICON", "TC_ALPHA",
        "TC_DISTANCE_FIELD_FONT", "TC_HDR_COMPRESSED", "TC_BC7", "TC_HALF_FLOAT", "TC_LQ",
        "TC_ENCODED_REFLECTION_CAPTURE", "TC_SINGLE_FLOAT", "TC_HDR_F32",
    },
    "TextureMipGenSettings": {
        "TMGS_FROM_TEXTURE_GROUP", "TMGS_SIM_AVERAGE", "TMGS_SHARPEN0", "TMGS_NO_MIPMAPS",
        "TMGS_LEAVE_EXISTING_MIPS", "TMGS_BLUR1", "TMGS_UNFILTERED", "TMGS_ANGULAR",
    },
    "TextureAddress": {"TA_WRAP", "TA_CLAMP", "TA_MIRROR"},
    "TextureFilter": {"TF_NEAREST", "TF_BILINEAR", "TF_TRILINEAR", "TF_DEFAULT"},
}


class _Enum:
    def __init__(self, kind):
        self.kind = kind

    def __getattr__(self, name):
        if name not in _ENUMS[self.kind]:
            raise AttributeError("unreal.{} has no {}".format(self.kind, name))
        return "{}.{}".format(self.kind, name)


for _kind in _ENUMS:
    globals()[_kind] = _Enum(_kind)

_PROPERTIES = {
    ".fga": {"intensity"},
    ".png": {"compression_settings", "srgb", "mip_gen_settings", "filter", "address_x", "address_y"},
    ".exr": {"compression_settings", "srgb", "mip_gen_settings", "filter", "address_x", "address_y"},
    ".dds": {"compression_settings", "srgb", "mip_gen_settings", "filter", "address_mode"},
}


class _Asset:
    def __init__(self, path, source):
        self.path, self.source = path, source

    def set_editor_property(self, name, value):
        ext = os.path.splitext(self.source)[1]
        if name not in _PROPERTIES[ext]:
            raise AttributeError("an asset from {} has no property {}".format(ext, name))
        calls.append(["set", os.path.basename(self.source), name, value])


_assets = {}


class AssetImportTask:
    _FIELDS = {"filename", "destination_path", "destination_name", "automated", "replace_existing", "save"}

    def __init__(self):
        self.props = {}

    def set_editor_property(self, name, value):
        if name not in self._FIELDS:
            raise AttributeError("AssetImportTask has no " + name)
        self.props[name] = value

    def get_editor_property(self, name):
        if name == "imported_object_paths":
            return self.props.get("imported", [])
        return self.props[name]


class _Tools:
    def import_asset_tasks(self, tasks):
        for t in tasks:
            source = t.props["filename"]
            assert os.path.isfile(source), source
            # The asset is named destination_name, or else after the file without its
            # extension, so wind_0000.exr and wind_0000.fga would land on one path.
            name = t.props.get("destination_name") or os.path.splitext(os.path.basename(source))[0]
            path = t.props["destination_path"] + "/" + name
            held = _assets.get(path)
            if held is not None and os.path.basename(held.source) != os.path.basename(source):
                # Unreal would replace the first asset with the second (or ask): refuse.
                raise RuntimeError("two files import onto {}: {} and {}".format(
                    path, os.path.basename(held.source), os.path.basename(source)))
            _assets[path] = _Asset(path, source)
            t.props["imported"] = [path]
            calls.append(["import", os.path.basename(source), t.props["destination_path"],
                          t.props["replace_existing"], t.props["automated"], path])


class AssetToolsHelpers:
    @staticmethod
    def get_asset_tools():
        return _Tools()


class EditorAssetLibrary:
    @staticmethod
    def load_asset(path):
        return _assets[path]

    @staticmethod
    def save_loaded_asset(asset):
        calls.append(["save", os.path.basename(asset.source)])
        return True


_ticks = []


def register_slate_post_tick_callback(f):
    _ticks.append(f)
    return len(_ticks)


def log(text):
    calls.append(["log", text])
