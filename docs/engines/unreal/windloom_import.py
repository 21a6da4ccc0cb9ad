"""Import a windloom bake into Unreal Editor with the settings its manifest.json gives.

Run it from the editor's Python console or Output Log (the Python Editor Script Plugin on):

    py "C:/path/to/windloom_import.py" "C:/path/to/bake" /Game/Wind
    py "C:/path/to/windloom_import.py" "C:/path/to/bake" /Game/Wind --watch

It reads `engines.unreal` of the bake's manifest.json and imports every file listed there into
the content folder, each file to an asset of its own named after it with its extension
(`wind_0000.exr` -> `/Game/Wind/wind_0000_exr`, `wind_0000.fga` -> `wind_0000_fga`),
replacing the earlier import of the same file: the FGA vector fields with
their Intensity, the atlas, the EXRs and the DDS volume as textures with the compression,
sRGB, mip, address and filter settings the manifest names (Unreal's own enum names), so the
Niagara and material set-ups in docs/engines/unreal.md read the wind in cm/s. With --watch it
polls manifest.json twice a second and imports again whenever its `sequence` changes (a
`windloom bake --watch` or the editor's Live export re-baked), reading the files and then the
manifest again so that it never imports half of one bake and half of another.
"""

import json
import os
import sys

import unreal


def read_manifest(folder):
    """The bake's manifest, or None when the folder holds no windloom bake."""
    try:
        with open(os.path.join(folder, "manifest.json"), encoding="utf-8") as f:
            m = json.load(f)
    except (OSError, ValueError):
        return None
    if m.get("format") != "windloom-bake":
        return None
    return m


def enum(kind, name):
    """An Unreal enum value by the name the manifest gives (e.g. TC_HDR)."""
    return getattr(getattr(unreal, kind), name)


def texture_settings(texture, settings):
    """Applies a manifest texture block to a texture asset."""
    texture.set_editor_property(
        "compression_settings", enum("TextureCompressionSettings", settings["compression_settings"])
    )
    texture.set_editor_property("srgb", settings["srgb"])
    texture.set_editor_property(
        "mip_gen_settings", enum("TextureMipGenSettings", settings["mip_gen_settings"])
    )
    texture.set_editor_property("filter", enum("TextureFilter", settings["filter"]))
    if "address_mode" in settings:
        # A volume texture: one address mode for its three axes.
        texture.set_editor_property("address_mode", enum("TextureAddress", settings["address_mode"]))
    else:
        texture.set_editor_property("address_x", enum("TextureAddress", settings["address_x"]))
        texture.set_editor_property("address_y", enum("TextureAddress", settings["address_y"]))


def asset_name(file_name):
    """The asset a bake file imports to: its name with the extension folded in
    (wind_0000.exr -> wind_0000_exr), so that wind_0000.exr and wind_0000.fga, which Unreal
    would otherwise both name wind_0000, each keep an asset of their own."""
    stem, ext = os.path.splitext(file_name)
    return stem + "_" + ext.lstrip(".").lower()


def import_files(folder, names, destination):
    """Imports `names` from the bake folder, each to its own asset (`asset_name`); returns
    the imported assets in the same order."""
    tasks = []
    for name in names:
        task = unreal.AssetImportTask()
        task.set_editor_property("filename", os.path.join(folder, name))
        task.set_editor_property("destination_path", destination)
        task.set_editor_property("destination_name", asset_name(name))
        task.set_editor_property("automated", True)
        task.set_editor_property("replace_existing", True)
        task.set_editor_property("save", False)
        tasks.append(task)
    unreal.AssetToolsHelpers.get_asset_tools().import_asset_tasks(tasks)
    assets = []
    for task, name in zip(tasks, names):
        paths = task.get_editor_property("imported_object_paths")
        if not paths:
            raise RuntimeError("windloom: Unreal did not import " + name)
        assets.append(unreal.EditorAssetLibrary.load_asset(paths[0]))
    return assets


def import_bake(folder, destination="/Game/Wind"):
    """Imports a bake; returns {file name: asset} and the manifest's sequence, or None when
    the bake changed while it was read (import again)."""
    m = read_manifest(folder)
    if m is None:
        raise RuntimeError("windloom: " + folder + " holds no windloom manifest.json")
    ue = m.get("engines", {}).get("unreal")
    if ue is None:
        raise RuntimeError("windloom: this bake has no file Unreal reads; bake fga, atlas, exr or dds")
    imported = {}
    fields = ue.get("vector_field_static")
    if fields:
        for name, asset in zip(fields["files"], import_files(folder, fields["files"], destination)):
            asset.set_editor_property("intensity", fields["intensity"])
            imported[name] = asset
    atlas = ue.get("niagara_atlas")
    if atlas:
        (asset,) = import_files(folder, [atlas["file"]], destination)
        texture_settings(asset, atlas["texture"])
        imported[atlas["file"]] = asset
    material = ue.get("material_texture")
    if material:
        for name, asset in zip(material["files"], import_files(folder, material["files"], destination)):
            texture_settings(asset, material["texture"])
            imported[name] = asset
    volume = ue.get("volume_texture")
    if volume:
        for name, asset in zip(volume["files"], import_files(folder, volume["files"], destination)):
            texture_settings(asset, volume)
            imported[name] = asset
    # The files read belong to the manifest read only if it is still the same bake.
    again = read_manifest(folder)
    if again is None or again.get("sequence") != m.get("sequence"):
        return None
    for asset in imported.values():
        unreal.EditorAssetLibrary.save_loaded_asset(asset)
    return imported, m.get("sequence")


def watch(folder, destination="/Game/Wind", seconds=0.5):
    """Imports the bake now and again whenever its sequence changes; returns the tick handle
    (unreal.unregister_slate_post_tick_callback(handle) stops it)."""
    shown = None
    waited = 0.0

    def tick(delta):
        nonlocal shown, waited
        waited += delta
        if waited < seconds:
            return
        waited = 0.0
        m = read_manifest(folder)
        if m is None or m.get("sequence") == shown:
            return
        done = import_bake(folder, destination)
        if done is not None:
            shown = done[1]
            unreal.log("windloom: imported bake {} from {}".format(done[1], folder))

    return unreal.register_slate_post_tick_callback(tick)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--watch"]
    if not args:
        raise SystemExit("usage: windloom_import.py BAKE_FOLDER [/Game/Folder] [--watch]")
    destination = args[1] if len(args) > 1 else "/Game/Wind"
    if "--watch" in sys.argv:
        watch(args[0], destination)
    else:
        done = import_bake(args[0], destination)
        if done is None:
            raise SystemExit("windloom: a new bake landed while importing; run it again")
        unreal.log("windloom: imported {} files of bake {}".format(len(done[0]), done[1]))
