extends Node
## The windloom add-on in a real Godot runtime (tests/godot/run.py builds the .pck and reads
## what this prints). Every line for the harness starts with "WL ":
##   WL READ <tag> <width> <height> <base64 RGBA8>   wind read back from the GPU
##   WL PNG <name> <base64 PNG>   a picture of what was drawn
##   WL WIND <tag> <outside> <format> <sample> <base64 f64: x y z t wx wy wz, a point after another>
##                     the gameplay wind (WindloomField) at points and times
##   WL INFO <text>    WL FAIL <text>    WL DONE
## The harness compares each READ with the bake's own files; this script only drives the
## add-on as a game would: the exported-style bake in res://wind (imported resources only),
## the demo scene over it, then bakes copied into user://wind as files (re-bake, broken bake).

const READBACK := preload("res://check/readback.gdshader")

var viewport: SubViewport
var rect: ColorRect
var material: ShaderMaterial


func _ready() -> void:
	viewport = SubViewport.new()
	viewport.transparent_bg = true
	viewport.render_target_update_mode = SubViewport.UPDATE_ALWAYS
	add_child(viewport)
	rect = ColorRect.new()
	viewport.add_child(rect)
	material = ShaderMaterial.new()
	material.shader = READBACK
	rect.material = material
	await _run()
	print("WL DONE")
	get_tree().quit(0)


func _fail(text: String) -> void:
	print("WL FAIL " + text)


func _run() -> void:
	await _broken_shader()
	await _unset()
	await _exported()
	await _demo()
	await _files()
	_gameplay()


## Draws the deliberately broken shader once: Godot must report its error.
func _broken_shader() -> void:
	var broken := ShaderMaterial.new()
	broken.shader = load("res://check/broken.gdshader")
	var r := ColorRect.new()
	r.size = Vector2(8, 8)
	r.material = broken
	viewport.size = Vector2i(8, 8)
	viewport.add_child(r)
	await _frames(2)
	r.queue_free()
	print("WL INFO drew broken.gdshader")


## The shaders with no bake set: the wind must be zero (a flowmap's default decodes to
## -scale, a float texture's white to 1 m/s, unless the shader guards it).
func _unset() -> void:
	material.set_shader_parameter("cells", Vector2i(16, 8))
	material.set_shader_parameter("layers", 4)
	material.set_shader_parameter("mode", 0)
	await _read("unset-steady", Vector2i(32, 8))
	material.set_shader_parameter("use_atlas", true)
	material.set_shader_parameter("atlas_scale", 7.0)
	await _read("unset-png-atlas", Vector2i(32, 8))
	material.set_shader_parameter("atlas_is_float", true)
	await _read("unset-float-atlas", Vector2i(32, 8))
	material.set_shader_parameter("mode", 1)
	await _read("unset-volume", Vector2i(48, 32))
	material.set_shader_parameter("use_atlas", false)
	material.set_shader_parameter("atlas_is_float", false)


func _frames(n: int) -> void:
	for i in n:
		await RenderingServer.frame_post_draw


## Renders the readback shader at `size` and prints its pixels under `tag`.
func _read(tag: String, size: Vector2i) -> void:
	viewport.size = size
	rect.size = Vector2(size)
	material.set_shader_parameter("pixels", size)
	await _frames(2)
	var image := viewport.get_texture().get_image()
	if image.get_format() != Image.FORMAT_RGBA8:
		image.convert(Image.FORMAT_RGBA8)
	print("WL READ %s %d %d %s" % [tag, image.get_width(), image.get_height(), Marshalls.raw_to_base64(image.get_data())])


## A WindloomWind on `dir` driving the readback material (as grass and particles).
func _wind(dir: String, with_volume: bool) -> WindloomWind:
	var wind := WindloomWind.new()
	wind.bake_dir = dir
	wind.poll_seconds = 1e9  # the check calls reload_if_changed itself
	wind.grass_materials = [material]
	if with_volume:
		wind.particle_materials = [material]
	add_child(wind)
	wind.set_process(false)  # the check sets the volume's clock itself
	return wind


## Every atlas frame (or the steady field) and every volume frame, read back.
func _read_bake(prefix: String, wind: WindloomWind, m: Dictionary) -> void:
	var nx := int(m["grid"][0])
	var ny := int(m["grid"][1])
	var p: Dictionary = m["engines"]["godot"]["shader_parameters"]
	material.set_shader_parameter("cells", Vector2i(nx, ny))
	material.set_shader_parameter("mode", 0)
	var frames := int(p["atlas_frames"]) if p["use_atlas"] else 1
	for k in frames:
		material.set_shader_parameter("check_time", (k + 0.5) / float(p["atlas_fps"]))
		await _read("%s-2d-%d" % [prefix, k], Vector2i(2 * nx, ny))
	if wind.volumes.is_empty():
		return
	var layers := int(m["profile"]["layers"])
	material.set_shader_parameter("mode", 1)
	material.set_shader_parameter("layers", layers)
	# Playback a quarter of the way from frame k to k + 1, as WindloomWind plays it.
	for k in wind.volumes.size():
		wind.clock = (k + 0.25) / wind.volume_fps
		wind._play_volume()
		await _read("%s-volume-%d" % [prefix, k], Vector2i(3 * nx, ny * layers))


func _exported() -> void:
	var m := WindloomBake.read_manifest("res://wind")
	if m.is_empty():
		_fail("no manifest in res://wind")
		return
	print("WL INFO exported: reads_imported=%s web=%s" % [WindloomBake.reads_imported("res://wind"), OS.has_feature("web")])
	var wind := _wind("res://wind", true)
	if wind.sequence != int(m["sequence"]):
		_fail("exported: the bake did not load: " + wind.last_error)
		return
	await _read_bake("exported", wind, m)
	_check_wind("exported", wind.field, m)
	wind.queue_free()
	# An export made without importing the bake first: its manifest, no imported textures.
	var bare := _wind("res://wind_not_imported", true)
	if bare.sequence != -1 or not bare.last_error.contains("is not an imported"):
		_fail("not imported: sequence %d, error \"%s\"" % [bare.sequence, bare.last_error])
	else:
		print("WL INFO not imported: reported \"%s\"" % bare.last_error)
	bare.queue_free()


## The demo as shipped, over res://wind: its grass and particles drawn for a while.
func _demo() -> void:
	var demo: Node = load("res://demo/demo.tscn").instantiate()
	# Chromium's software WebGL (SwiftShader) takes ~13 s a frame for the demo's 4,000
	# particles; a GPU takes well under a millisecond.
	demo.blades = 4000
	demo.particles_amount = 64
	add_child(demo)
	print("WL INFO demo built, %d ms" % Time.get_ticks_msec())
	await _frames(30)
	print("WL INFO demo drew 30 frames, %d ms" % Time.get_ticks_msec())
	# What the demo showed, for a person to look at (run.py --keep writes demo.png).
	var shot := get_viewport().get_texture().get_image()
	print("WL PNG demo " + Marshalls.raw_to_base64(shot.save_png_to_buffer()))
	var loaded := -1
	for child in demo.get_children():
		if child is WindloomWind:
			loaded = child.sequence
			if not child.last_error.is_empty():
				_fail("demo: " + child.last_error)
	print("WL INFO demo drew 30 frames on bake %d" % loaded)
	if loaded < 0:
		_fail("demo: no bake loaded")
	demo.queue_free()
	await _frames(1)


## Copies the files of res://src/<name> into `to` (user://wind by default), the manifest
## last (as a bake lands: the manifest names the files once they are there). Returns `to`.
func _land(name: String, to := "user://wind") -> String:
	DirAccess.make_dir_recursive_absolute(to)
	var from := "res://src/" + name
	for file in DirAccess.get_files_at(from):
		if file != "manifest.json":
			_copy(from.path_join(file), to.path_join(file))
	_copy(from.path_join("manifest.json"), to.path_join("manifest.json"))
	return to


func _copy(from: String, to: String) -> void:
	var data := FileAccess.get_file_as_bytes(from)
	var f := FileAccess.open(to, FileAccess.WRITE)
	f.store_buffer(data)
	f.close()


func _files() -> void:
	_land("a")
	var m := WindloomBake.read_manifest("user://wind")
	var wind := _wind("user://wind", true)
	if wind.sequence != int(m.get("sequence", -2)):
		_fail("files: bake a did not load: " + wind.last_error)
		return
	await _read_bake("files", wind, m)
	_check_wind("files", wind.field, m)

	# A re-bake lands: the node follows it at its next poll.
	_land("b")
	m = WindloomBake.read_manifest("user://wind")
	if not wind.reload_if_changed() or wind.sequence != int(m["sequence"]):
		_fail("rebake: bake b did not load: " + wind.last_error)
		return
	print("WL INFO rebake: now on bake %d" % wind.sequence)
	await _read_bake("rebake", wind, m)
	_check_wind("rebake", wind.field, m)

	# A broken bake lands (a file that is not an image): it is reported, bake b stays.
	var before := wind.sequence
	var failures := []
	wind.bake_failed.connect(func(seq, message): failures.append([seq, message]))
	_land("broken")
	if wind.reload_if_changed() or wind.sequence != before or failures.size() != 1:
		_fail("broken: sequence %d, failures %s" % [wind.sequence, failures])
		return
	print("WL INFO broken: reported \"%s\", kept bake %d" % [failures[0][1], wind.sequence])
	await _read_bake("broken", wind, m)
	if wind.field == null or wind.field.sequence != before:
		_fail("broken: the gameplay wind did not stay on bake %d" % before)


## The gameplay wind of bakes no node shows: a 16-bit PNG flowmap alone (read at 16 bits),
## and a terrain bake (the log law over its heights), then bakes that lie.
func _gameplay() -> void:
	for name in ["c", "terrain"]:
		var dir := _land(name, "user://" + name)
		var m: Dictionary = WindloomField.read_manifest(dir)
		var field = WindloomField.open(dir)
		if field is String:
			_fail("%s: %s" % [name, field])
			continue
		_check_wind(name, field, m)
	# A bake for shaders alone (a PNG atlas): the materials load, wind_at answers zero (and
	# the node warns once), not a failed bake.
	var atlas := _wind(_land("d", "user://d"), false)
	if atlas.sequence < 0 or atlas.field != null or atlas.wind_at(Vector3(10, 2, 10), 0.3) != Vector3.ZERO:
		_fail("atlas only: sequence %d, field %s, error \"%s\"" % [atlas.sequence, atlas.field, atlas.last_error])
	else:
		print("WL INFO atlas only: bake %d on the materials, wind_at zero" % atlas.sequence)
	atlas.queue_free()
	_lies()


## Lying bakes: each refused in one line naming what is wrong, none read.
func _lies() -> void:
	var dir := "user://c"
	var m: Dictionary = WindloomField.read_manifest(dir)
	var cases := {
		"a name outside the folder": "files[0].name",
		"2^40 frames": "frames",
		"a file longer than listed": "bytes",
		"a grid of 2^20 cells a side": "axes",
		"an infinite scale": "scale",
		"version 9": "version",
	}
	for what in cases:
		var d: Dictionary = m.duplicate(true)
		_lie(d, what)
		var got = WindloomField.open(dir, d)
		if not got is String:
			_fail("lie: %s was read" % what)
		elif not got.contains(cases[what]) or got.contains("\n") or got.length() > WindloomField.MAX_ERROR_CHARS:
			_fail("lie: %s: \"%s\" does not name %s in one line" % [what, got, cases[what]])
		else:
			print("WL INFO lie refused: %s: %s" % [what, got])


func _lie(d: Dictionary, what: String) -> void:
	match what:
		"a name outside the folder":
			d["files"][0]["name"] = "../c/" + d["files"][0]["name"]
		"2^40 frames":
			d["frames"]["count"] = 1099511627776.0
		"a file longer than listed":
			for f in d["files"]:
				f["bytes"] = int(f["bytes"]) - 1
		"a grid of 2^20 cells a side":
			for f in d["files"]:
				f["axes"]["index"][0]["cells"] = 1048576.0
		"an infinite scale":
			for f in d["files"]:
				for c in f["encoding"]["channels"]:
					c["scale"] = INF
		"version 9":
			d["version"] = 9


## WindloomField's answers, printed for the harness to ask windloom's runtime the same: at
## every cell's centre at every frame's time at the reference height above the ground, then
## at points spread to a quarter of the level beyond every edge, from below the ground to
## above the profile's top, at times before, between and after the frames (and NaN and
## infinite ones), in each of the three Outside modes. wind_at_many must answer what
## wind_at does, to the bit.
func _check_wind(tag: String, field: WindloomField, m: Dictionary) -> void:
	if field == null:
		_fail("%s: no gameplay wind" % tag)
		return
	print("WL INFO %s: gameplay wind from %s (%s), %d frames of %d × %d, %d bytes" % [tag, field.format, "imported" if field.from_imported else "files", field.frames(), field.grid.x, field.grid.y, field.memory_bytes()])
	var href := float(m["profile"]["reference_height"])
	var top := float(m["profile"]["top"])
	var lo := field.bounds_min
	var hi := field.bounds_max
	var size := hi - lo
	var points := PackedVector3Array()
	var times := PackedFloat64Array()
	for k in field.frames():
		for j in field.grid.y:
			for i in field.grid.x:
				var x := lo.x + (i + 0.5) * size.x / field.grid.x
				var z := lo.y + (j + 0.5) * size.y / field.grid.y
				points.append(_f32(Vector3(x, field.ground_at(x, z) + href, z)))
				times.append(k / field.fps)
	_print_wind(tag, field, Outside.CLAMP, points, times)
	var rng := RandomNumberGenerator.new()
	rng.seed = 76
	points = PackedVector3Array()
	times = PackedFloat64Array()
	var span := maxf(field.duration(), 1.0 / field.fps)
	for n in 400:
		var p := Vector3(rng.randf_range(lo.x - 0.25 * size.x, hi.x + 0.25 * size.x), rng.randf_range(-1.0, 1.3 * top),
				rng.randf_range(lo.y - 0.25 * size.y, hi.y + 0.25 * size.y))
		points.append(_f32(p))
		times.append(rng.randf_range(-1.5 * span - 1.0, 2.5 * span + 1.0))
	times[0] = NAN
	times[1] = INF
	times[2] = -INF
	times[3] = 2.6e6 + 0.37  # a month of game clock
	for mode in [Outside.CLAMP, Outside.ZERO, Outside.WRAP]:
		_print_wind(tag, field, mode, points, times)
	# The batch form at one time: wind_at's answers, to the bit.
	field.outside = Outside.WRAP
	var many := field.wind_at_many(points, times[5])
	for n in points.size():
		if many[n] != field.wind_at(points[n], times[5]):
			_fail("%s: wind_at_many gives %s at %s, wind_at %s" % [tag, many[n], points[n], field.wind_at(points[n], times[5])])
			break
	field.outside = Outside.CLAMP


const Outside = WindloomField.Outside


## A point as f32 (what the runtime's positions are), so both read the same point.
func _f32(p: Vector3) -> Vector3:
	var a := PackedFloat32Array([p.x, p.y, p.z])
	return Vector3(a[0], a[1], a[2])


func _print_wind(tag: String, field: WindloomField, mode: int, points: PackedVector3Array, times: PackedFloat64Array) -> void:
	field.outside = mode
	var out := PackedFloat64Array()
	var started := Time.get_ticks_usec()
	for n in points.size():
		var w := field.wind_at(points[n], times[n])
		out.append_array([points[n].x, points[n].y, points[n].z, times[n], w.x, w.y, w.z])
	var us := Time.get_ticks_usec() - started
	print("WL INFO %s: %d wind_at calls (%s) in %d ms, %.1f µs each" % [tag, points.size(), ["clamp", "zero", "wrap"][mode], us / 1000, float(us) / points.size()])
	print("WL WIND %s %s %s %s %s" % [tag, ["clamp", "zero", "wrap"][mode], field.format, field.sample, Marshalls.raw_to_base64(out.to_byte_array())])
