@tool
class_name WindloomBake
extends RefCounted
## Reads a windloom bake folder by its manifest.json (docs/EXPORT.md): the import settings
## of its textures, the textures themselves straight from disk, and the uniforms of
## windloom_grass.gdshader and windloom_particles.gdshader.


## The bake's manifest, or an empty Dictionary where the folder holds no windloom bake.
static func read_manifest(dir: String) -> Dictionary:
	var text := FileAccess.get_file_as_string(dir.path_join("manifest.json"))
	if text.is_empty():
		return {}
	var m = JSON.parse_string(text)
	if typeof(m) != TYPE_DICTIONARY or m.get("format", "") != "windloom-bake":
		return {}
	return m


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


## A baked image as a texture, read from disk without the import cache (an EXR keeps its
## floats; a PNG loads at 8 bits a channel), so a new bake shows at once.
static func load_texture(dir: String, name: String) -> ImageTexture:
	var image := Image.load_from_file(ProjectSettings.globalize_path(dir.path_join(name)))
	if image == null:
		return null
	return ImageTexture.create_from_image(image)


## The volume's EXR slices as a Texture3D: `layers` slices stacked down the image.
static func load_volume(dir: String, name: String, layers: int) -> ImageTexture3D:
	var image := Image.load_from_file(ProjectSettings.globalize_path(dir.path_join(name)))
	if image == null or layers < 1:
		return null
	var height := image.get_height() / layers
	var slices: Array[Image] = []
	for k in layers:
		slices.append(image.get_region(Rect2i(0, k * height, image.get_width(), height)))
	var texture := ImageTexture3D.new()
	texture.create(image.get_format(), image.get_width(), height, layers, false, slices)
	return texture


## Sets windloom_grass.gdshader's uniforms on `material` from the manifest.
static func apply_grass(material: ShaderMaterial, dir: String, m: Dictionary) -> void:
	var p: Dictionary = m["engines"]["godot"]["shader_parameters"]
	material.set_shader_parameter("bounds_min", Vector2(p["bounds_min"][0], p["bounds_min"][1]))
	material.set_shader_parameter("bounds_max", Vector2(p["bounds_max"][0], p["bounds_max"][1]))
	if p.has("wind_tex"):
		material.set_shader_parameter("wind_tex", load_texture(dir, p["wind_tex"]))
	material.set_shader_parameter("use_atlas", p["use_atlas"])
	if p["use_atlas"]:
		material.set_shader_parameter("wind_atlas", load_texture(dir, p["wind_atlas"]))
		material.set_shader_parameter("atlas_grid", Vector2i(p["atlas_grid"][0], p["atlas_grid"][1]))
		material.set_shader_parameter("atlas_frames", int(p["atlas_frames"]))
		material.set_shader_parameter("atlas_fps", float(p["atlas_fps"]))
		material.set_shader_parameter("atlas_scale", float(p["atlas_scale"]))
		material.set_shader_parameter("atlas_is_float", p["atlas_is_float"])


## Sets windloom_particles.gdshader's uniforms on `material` from the manifest's volume.
static func apply_particles(material: ShaderMaterial, dir: String, m: Dictionary) -> void:
	var v: Dictionary = m["engines"]["godot"].get("volume", {})
	if v.is_empty():
		push_warning("windloom: this bake has no volume; bake --format dds")
		return
	var layers := int(v["import"]["slices/vertical"])
	material.set_shader_parameter("wind_volume", load_volume(dir, v["files"][0], layers))
	material.set_shader_parameter("volume_min", Vector3(v["volume_min"][0], v["volume_min"][1], v["volume_min"][2]))
	material.set_shader_parameter("volume_size", Vector3(v["volume_size"][0], v["volume_size"][1], v["volume_size"][2]))
