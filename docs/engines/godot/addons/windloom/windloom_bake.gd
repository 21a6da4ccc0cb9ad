@tool
class_name WindloomBake
extends RefCounted
## Reads a windloom bake folder by its manifest.json (docs/EXPORT.md): the import settings
## of its textures, the textures, and the uniforms of windloom_wind.gdshaderinc and
## windloom_volume.gdshaderinc (used by the grass and particle shaders).
##
## Where the textures come from depends on where the game runs (`reads_imported`):
## - an exported game, `res://` folder: the resources the editor imported (`.import` +
##   `.ctex`); an export carries those, not the source files. Any platform, the web too.
## - the editor, or a `user://` or absolute folder: the files themselves, read from disk
##   without the import cache, so a re-bake shows at once. On the web Godot cannot read EXR
##   at run time (its TinyEXR is built with threads, the web build has none, and the engine
##   aborts), so there the bake is read from its raw floats, its DDS volume or its PNGs,
##   whichever the manifest lists.
## The loaders return the texture, or a String saying what failed.


## The bake's manifest, or an empty Dictionary where the folder holds no windloom bake.
static func read_manifest(dir: String) -> Dictionary:
	if not FileAccess.file_exists(dir.path_join("manifest.json")):
		return {}
	var text := FileAccess.get_file_as_string(dir.path_join("manifest.json"))
	if text.is_empty():
		return {}
	var m = JSON.parse_string(text)
	if typeof(m) != TYPE_DICTIONARY or m.get("format", "") != "windloom-bake":
		return {}
	return m


## Whether textures in `dir` are loaded as the editor imported them (an exported game's
## `res://`), not read from their files.
static func reads_imported(dir: String) -> bool:
	return dir.begins_with("res://") and not OS.has_feature("editor")


## Whether this runtime can read the file `name` in `dir`.
static func can_read(dir: String, name: String) -> bool:
	if reads_imported(dir):
		return true
	return not (name.get_extension().to_lower() == "exr" and OS.has_feature("web"))


## Writes each texture's `.import` file with the manifest's `engines.godot` settings
## (Lossless, no mipmaps, Detect 3D off; the volume as a Texture3D of its slices), keeping
## what Godot wrote there (its uid). Returns the paths to reimport.
static func write_import_settings(dir: String, m: Dictionary) -> PackedStringArray:
	var paths := PackedStringArray()
	var godot: Dictionary = m.get("engines", {}).get("godot", {})
	for name in godot.get("textures", []):
		paths.append(_write_import(dir.path_join(name), "texture", "CompressedTexture2D", godot["import"]))
	var volume: Dictionary = godot.get("volume", {})
	for name in volume.get("files", []):
		paths.append(_write_import(dir.path_join(name), volume["importer"], volume["type"], volume["import"]))
	# The terrain's heights are read by WindloomField at 16 bits, from the file itself: Keep
	# File, so an export carries it as it is (an imported PNG keeps 8 bits).
	var terrain = m.get("terrain")
	if terrain is Dictionary and terrain.get("file") is String:
		var cfg := ConfigFile.new()
		var path := dir.path_join(terrain["file"])
		cfg.set_value("remap", "importer", "keep")
		cfg.save(path + ".import")
		paths.append(path)
	return paths


static func _write_import(path: String, importer: String, type: String, params: Dictionary) -> String:
	var cfg := ConfigFile.new()
	cfg.load(path + ".import")  # absent on the first import: starts empty
	cfg.set_value("remap", "importer", importer)
	cfg.set_value("remap", "type", type)
	for key in params:
		cfg.set_value("params", key, params[key])
	cfg.save(path + ".import")
	return path


## The manifest's entry for file `name`, or an empty Dictionary.
static func file_entry(m: Dictionary, name: String) -> Dictionary:
	for f in m.get("files", []):
		if f.get("name", "") == name:
			return f
	return {}


## The names of the manifest's files of `format`, in frame order.
static func files_of(m: Dictionary, format: String) -> Array:
	var names := []
	for f in m.get("files", []):
		if f.get("format", "") == format:
			names.append(f["name"])
	return names


## A baked image as a texture: the imported resource, or the file read from disk (an EXR
## keeps its floats; a PNG loads at 8 bits a channel).
static func load_texture(dir: String, name: String) -> Variant:
	var path := dir.path_join(name)
	if reads_imported(dir):
		return _imported(path, "Texture2D")
	if not can_read(dir, name):
		return "%s: EXR cannot be read at run time on the web" % path
	if not FileAccess.file_exists(path):
		return "%s is missing" % path
	var image := Image.load_from_file(ProjectSettings.globalize_path(path))
	if image == null or image.is_empty():
		return "%s could not be read as an image" % path
	return ImageTexture.create_from_image(image)


## The resource the editor imported for `path` (an exported game carries it, not the file),
## or a String.
static func _imported(path: String, type: String) -> Variant:
	var resource = ResourceLoader.load(path, type)
	if resource == null:
		return "%s is not an imported %s (import the bake in the editor before exporting)" % [path, type]
	return resource


## Frames `first` … `first + count - 1` of the raw bake `name` (little-endian f32 pairs,
## [frame][row][column][x, z]) as RG float images.
static func load_raw_frames(dir: String, name: String, m: Dictionary, first: int, count: int) -> Variant:
	var path := dir.path_join(name)
	var nx := int(m["grid"][0])
	var ny := int(m["grid"][1])
	var bytes := nx * ny * 8
	var file := FileAccess.open(path, FileAccess.READ)
	if file == null:
		return "%s could not be opened (%s)" % [path, error_string(FileAccess.get_open_error())]
	if file.get_length() < (first + count) * bytes:
		return "%s holds %d bytes, short of %d frames of %d × %d" % [path, file.get_length(), first + count, nx, ny]
	file.seek(first * bytes)
	var frames: Array[Image] = []
	for k in count:
		frames.append(Image.create_from_data(nx, ny, false, Image.FORMAT_RGF, file.get_buffer(bytes)))
	return frames


## The steady field for `wind_tex`: the first EXR where it can be read, else the raw
## floats' first frame, else the first PNG flowmap. Returns [texture, scale, offset]
## (value = stored × scale + offset) or a String.
static func load_steady(dir: String, m: Dictionary) -> Variant:
	var p: Dictionary = m["engines"]["godot"]["shader_parameters"]
	var errors := PackedStringArray()
	if p.has("wind_tex") and can_read(dir, p["wind_tex"]):
		var t = load_texture(dir, p["wind_tex"])
		if t is Texture2D:
			return [t, Vector2.ONE, Vector2.ZERO]
		errors.append(t)
	var raw := files_of(m, "raw")
	if not raw.is_empty() and not reads_imported(dir):
		var frames = load_raw_frames(dir, raw[0], m, 0, 1)
		if frames is Array:
			return [ImageTexture.create_from_image(frames[0]), Vector2.ONE, Vector2.ZERO]
		errors.append(frames)
	var pngs := files_of(m, "png16") + files_of(m, "png8")  # 16-bit first: Godot keeps 8 of either
	if not pngs.is_empty():
		var t = load_texture(dir, pngs[0])
		if t is Texture2D:
			var c: Array = file_entry(m, pngs[0])["encoding"]["channels"]
			return [t, Vector2(c[0]["scale"], c[1]["scale"]), Vector2(c[0]["offset"], c[1]["offset"])]
		errors.append(t)
	if errors.is_empty():
		return "the bake has no 2D wind texture this runtime can read (bake --format raw or png16)"
	return "; ".join(errors)


## The animated field for `wind_atlas`: atlas.exr where it can be read, else an atlas of the
## raw floats' frames, else atlas.png. Returns [texture, is_float] or a String.
static func load_atlas(dir: String, m: Dictionary) -> Variant:
	var p: Dictionary = m["engines"]["godot"]["shader_parameters"]
	var errors := PackedStringArray()
	var exr := files_of(m, "atlas-exr")
	if not exr.is_empty() and can_read(dir, exr[0]):
		var t = load_texture(dir, exr[0])
		if t is Texture2D:
			return [t, true]
		errors.append(t)
	var raw := files_of(m, "raw")
	if not raw.is_empty() and not reads_imported(dir):
		var count := int(p["atlas_frames"])
		var frames = load_raw_frames(dir, raw[0], m, 0, count)
		if frames is Array:
			var nx := int(m["grid"][0])
			var ny := int(m["grid"][1])
			var columns := int(p["atlas_grid"][0])
			var rows := int(p["atlas_grid"][1])
			var atlas := Image.create_empty(columns * nx, rows * ny, false, Image.FORMAT_RGF)
			for k in count:
				atlas.blit_rect(frames[k], Rect2i(0, 0, nx, ny), Vector2i((k % columns) * nx, (k / columns) * ny))
			return [ImageTexture.create_from_image(atlas), true]
		errors.append(frames)
	var png := files_of(m, "atlas")
	if not png.is_empty():
		var t = load_texture(dir, png[0])
		if t is Texture2D:
			return [t, false]
		errors.append(t)
	return "; ".join(errors)


## Sets windloom_wind.gdshaderinc's uniforms (the grass shader's) on `material` from the
## manifest. Returns "" or what failed; on failure `material` may be half set.
static func apply_grass(material: ShaderMaterial, dir: String, m: Dictionary) -> String:
	var p: Dictionary = m["engines"]["godot"]["shader_parameters"]
	material.set_shader_parameter("bounds_min", Vector2(p["bounds_min"][0], p["bounds_min"][1]))
	material.set_shader_parameter("bounds_max", Vector2(p["bounds_max"][0], p["bounds_max"][1]))
	if p["use_atlas"]:
		var atlas = load_atlas(dir, m)
		if atlas is String:
			return atlas
		var is_float: bool = atlas[1]
		var png := files_of(m, "atlas")
		var scale := float(p["atlas_scale"])
		if not is_float and p["atlas_is_float"] and not png.is_empty():
			scale = -float(file_entry(m, png[0])["encoding"]["channels"][0]["offset"])
		material.set_shader_parameter("use_atlas", true)
		material.set_shader_parameter("wind_atlas", atlas[0])
		material.set_shader_parameter("atlas_is_float", is_float)
		material.set_shader_parameter("atlas_grid", Vector2i(p["atlas_grid"][0], p["atlas_grid"][1]))
		material.set_shader_parameter("atlas_frames", int(p["atlas_frames"]))
		material.set_shader_parameter("atlas_fps", float(p["atlas_fps"]))
		material.set_shader_parameter("atlas_scale", scale if not is_float else 1.0)
		material.set_shader_parameter("wind_tex", null)
		return ""
	var steady = load_steady(dir, m)
	if steady is String:
		return steady
	material.set_shader_parameter("use_atlas", false)
	material.set_shader_parameter("wind_atlas", null)
	material.set_shader_parameter("wind_tex", steady[0])
	material.set_shader_parameter("wind_tex_scale", steady[1])
	material.set_shader_parameter("wind_tex_offset", steady[2])
	return ""


## One volume frame: the imported Texture3D, the EXR slices read from disk, or (where EXR
## cannot be read) the DDS volume of the same frame. Returns a Texture3D or a String.
static func load_volume(dir: String, m: Dictionary, frame: int) -> Variant:
	var v: Dictionary = m["engines"]["godot"]["volume"]
	var name: String = v["files"][frame]
	var path := dir.path_join(name)
	if reads_imported(dir):
		return _imported(path, "Texture3D")
	var layers := int(v["import"]["slices/vertical"])
	if can_read(dir, name):
		if not FileAccess.file_exists(path):
			return "%s is missing" % path
		var image := Image.load_from_file(ProjectSettings.globalize_path(path))
		if image == null or image.is_empty() or layers < 1:
			return "%s could not be read as an image" % path
		var height := image.get_height() / layers
		var slices: Array[Image] = []
		for k in layers:
			slices.append(image.get_region(Rect2i(0, k * height, image.get_width(), height)))
		return _texture_3d(slices)
	var dds := name.get_basename() + ".dds"
	if file_entry(m, dds).is_empty():
		return "%s: EXR cannot be read at run time on the web, and the bake has no %s" % [path, dds]
	return load_dds_volume(dir.path_join(dds))


## A DDS volume as windloom writes it (WindloomFiles.dds_header) as a Texture3D, or a
## String.
static func load_dds_volume(path: String) -> Variant:
	var file := FileAccess.open(path, FileAccess.READ)
	if file == null:
		return "%s could not be opened (%s)" % [path, error_string(FileAccess.get_open_error())]
	var head = WindloomFiles.dds_header(file.get_buffer(148))
	if head is String:
		return "%s: %s" % [path, head]
	var width: int = head.width
	var height: int = head.height
	var depth: int = head.depth
	var format: int = head.format
	var bytes: int = width * height * head.texel_bytes
	if file.get_length() < 148 + depth * bytes:
		return "%s is shorter than its %d × %d × %d texels" % [path, width, height, depth]
	var slices: Array[Image] = []
	for k in depth:
		slices.append(Image.create_from_data(width, height, false, format, file.get_buffer(bytes)))
	return _texture_3d(slices)


static func _texture_3d(slices: Array[Image]) -> ImageTexture3D:
	var texture := ImageTexture3D.new()
	texture.create(slices[0].get_format(), slices[0].get_width(), slices[0].get_height(), slices.size(), false, slices)
	return texture


## Every volume frame of the bake, in order, or a String. A bake without a volume gives [].
static func load_volumes(dir: String, m: Dictionary) -> Variant:
	var volumes: Array[Texture3D] = []
	var v: Dictionary = m["engines"]["godot"].get("volume", {})
	for k in v.get("files", []).size():
		var t = load_volume(dir, m, k)
		if t is String:
			return t
		volumes.append(t)
	return volumes


## Sets windloom_volume.gdshaderinc's uniforms (the particle shader's) on `material`:
## its box, and frame 0 of `volumes`.
static func apply_particles(material: ShaderMaterial, m: Dictionary, volumes: Array[Texture3D]) -> void:
	var v: Dictionary = m["engines"]["godot"].get("volume", {})
	if v.is_empty():
		push_warning("windloom: this bake has no volume; bake --format dds")
		return
	material.set_shader_parameter("wind_volume", volumes[0])
	material.set_shader_parameter("wind_volume_next", volumes[0])
	material.set_shader_parameter("volume_blend", 0.0)
	material.set_shader_parameter("volume_min", Vector3(v["volume_min"][0], v["volume_min"][1], v["volume_min"][2]))
	material.set_shader_parameter("volume_size", Vector3(v["volume_size"][0], v["volume_size"][1], v["volume_size"][2]))
