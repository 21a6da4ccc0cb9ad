class_name WindloomField
extends RefCounted
## A bake's wind on the CPU, for a game's own code: the wind at a sail, a projectile, a flag,
## the player's ears. It follows the rules of windloom's runtime (docs/RUNTIME.md: "What it
## answers") in GDScript, so it runs wherever Godot runs: the editor, an exported game
## (reading its .pck), the web. `windloom sample BAKE` gives the runtime's own answers, and
## tests/godot/run.py compares the two at every cell of every frame and beyond every edge.
##
##     var field = WindloomField.open("res://wind")      # a WindloomField, or a String
##     var w: Vector3 = field.wind_at(global_position, seconds)
##
## - Space: bilinear between the cells' centres.
## - Height: the baked wind is the wind at the profile's reference height above the ground
##   (the bake's terrain, else y = 0); the log law carries it up and down: 0 at and below the
##   roughness length, the wind at the profile's top above it.
## - Time: frame k at t = k / fps, linear between frames; a looped bake wraps, a plain one
##   holds its first and last frames. `time` is a float (64 bits in GDScript): a clock a
##   month on reads the wind as precisely as one a minute on.
## - Beyond the baked rectangle, `outside` says: CLAMP (the edge's wind), ZERO, or WRAP (the
##   bake repeats, its ground too).
## - The wind is horizontal (y = 0), in Godot's axes, which are windloom's (x east, y up,
##   z south, m/s).
##
## What it reads, most precise first, as the runtime picks: the raw floats (`*.f32`), EXR
## (f32), the DDS volume (its layer nearest the reference height, the factor divided out),
## half-float EXR and DDS, the 16-bit PNG flowmaps (decoded here at 16 bits; Godot's own
## PNG loader keeps 8), the 8-bit ones. A file is read from disk (the editor, `user://`, a
## file an export carries as it is) or, for an EXR or PNG that an export carries only as
## imported, from the imported `.ctex`; EXR files are never read on the web (Godot's EXR
## reader aborts there). The terrain's `heights.png` must be a file (the add-on's import tool
## sets it to Keep File, so an export carries it as it is).
##
## A bake is untrusted input: every size is checked against the manifest and the limits below
## before anything is read, only plain file names inside the bake's folder are opened, a
## wind or height that is not a finite number refuses the bake, and every refusal is one
## line naming the file or the field.

enum Outside { CLAMP, ZERO, WRAP }

const MAX_FRAMES := 100000
const MAX_GRID_SIDE := 16384
## The most wind held (frames × cells × 8 bytes): 1 GiB.
const MAX_WIND_BYTES := 1 << 30
const MAX_MANIFEST_BYTES := 16 << 20
const MAX_ERROR_CHARS := 480

## What the wind is beyond the baked rectangle.
var outside: Outside = Outside.CLAMP
## The manifest's `sequence`.
var sequence := 0
## The format the wind was read from (`raw`, `exr`, `dds`, `png16`…) and its files.
var format := ""
var files := PackedStringArray()
## How those files store the wind: `f32`, `f16`, `unorm16` or `unorm8`.
var sample := ""
## Whether each file was read from an imported resource (`.ctex`) rather than the file.
var from_imported := false
var fps := 1.0
var looped := false
## The wind's grid and rectangle (x, z), metres.
var grid := Vector2i.ZERO
var bounds_min := Vector2.ZERO
var bounds_max := Vector2.ZERO

var _wind: Grid
## Per frame, nx × ny winds [x, z] at the reference height, row-major (rows along +z).
var _frames: Array[PackedFloat32Array] = []
var _law := false
var _z0 := 0.0
var _top := 0.0
var _at_reference := 1.0
var _ground: Grid
var _heights := PackedFloat32Array()
var _heights_on_wind_grid := false
# The moment of the last call: frames a, b and the weight of b.
var _a := 0
var _b := 0
var _w := 0.0


## A grid of cells over a world rectangle, sampled between the cells' centres.
class Grid:
	var nx: int
	var ny: int
	var lo: Vector2
	var hi: Vector2
	var per: Vector2
	# Where the last `locate` fell: the four corners' indices and the weights along x and z.
	var k00 := 0
	var k10 := 0
	var k01 := 0
	var k11 := 0
	var fx := 0.0
	var fz := 0.0

	func _init(cells_x: int, cells_z: int, minimum: Vector2, maximum: Vector2) -> void:
		nx = cells_x
		ny = cells_z
		lo = minimum
		hi = maximum
		per = Vector2(nx / (hi.x - lo.x), ny / (hi.y - lo.y))

	## Finds the cells around (x, z); false where `mode` is ZERO and the point is outside.
	## Every index is below nx × ny, whatever x and z are (NaN and infinities too).
	func locate(x: float, z: float, mode: int) -> bool:
		var gx := (x - lo.x) * per.x - 0.5
		var gz := (z - lo.y) * per.y - 0.5
		var i0: int
		var i1: int
		var j0: int
		var j1: int
		if mode == Outside.WRAP:
			var fx0 := floorf(gx)
			var fz0 := floorf(gz)
			i0 = mini(int(fposmod(fx0, nx)), nx - 1) if is_finite(fx0) else 0
			j0 = mini(int(fposmod(fz0, ny)), ny - 1) if is_finite(fz0) else 0
			i1 = (i0 + 1) % nx
			j1 = (j0 + 1) % ny
			fx = gx - fx0
			fz = gz - fz0
			if not is_finite(fx):
				fx = 0.0
			if not is_finite(fz):
				fz = 0.0
		else:
			if mode == Outside.ZERO and not (x >= lo.x and x <= hi.x and z >= lo.y and z <= hi.y):
				return false
			# A NaN becomes 0, the corner cell.
			gx = 0.0 if not (gx >= 0.0) else minf(gx, nx - 1)
			gz = 0.0 if not (gz >= 0.0) else minf(gz, ny - 1)
			i0 = int(gx)
			j0 = int(gz)
			i1 = mini(i0 + 1, nx - 1)
			j1 = mini(j0 + 1, ny - 1)
			fx = gx - i0
			fz = gz - j0
		k00 = j0 * nx + i0
		k10 = j0 * nx + i1
		k01 = j1 * nx + i0
		k11 = j1 * nx + i1
		return true

	## Bilinear between the corners `locate` found, of a plane of one value a cell.
	func blend(v: PackedFloat32Array) -> float:
		var a := v[k00] + (v[k10] - v[k00]) * fx
		var b := v[k01] + (v[k11] - v[k01]) * fx
		return a + (b - a) * fz


## The bake in `dir` (`res://wind`, `user://wind`, an absolute folder), read by its
## manifest.json (or `manifest`, already read): a WindloomField, or a String saying what is
## wrong in one line. `outside` is what it answers beyond the rectangle.
static func open(dir: String, manifest: Dictionary = {}, outside_mode: Outside = Outside.CLAMP) -> Variant:
	var m := manifest
	if m.is_empty():
		var read = read_manifest(dir)
		if read is String:
			return _line(read)
		m = read
	var field := WindloomField.new()
	field.outside = outside_mode
	var error := field._load(dir, m)
	if not error.is_empty():
		return _line(error)
	return field


## Whether the manifest lists files this reads (raw, EXR, DDS, PNG flowmaps): a bake of
## atlases and FGA alone has none.
static func holds_wind(m: Dictionary) -> bool:
	var listed = m.get("files")
	if not listed is Array:
		return false
	return listed.any(func(e): return e is Dictionary and not _kind(e).is_empty())


## The manifest in `dir` as a Dictionary, or a String.
static func read_manifest(dir: String) -> Variant:
	var path := dir.path_join("manifest.json")
	var f := FileAccess.open(path, FileAccess.READ)
	if f == null:
		return "%s: cannot be opened (%s)" % [path, error_string(FileAccess.get_open_error())]
	if f.get_length() > MAX_MANIFEST_BYTES:
		return "%s: %d bytes, more than a manifest's %d" % [path, f.get_length(), MAX_MANIFEST_BYTES]
	var json := JSON.new()
	if json.parse(f.get_buffer(f.get_length()).get_string_from_utf8()) != OK:
		return "%s:%d: %s" % [path, json.get_error_line(), json.get_error_message()]
	if typeof(json.data) != TYPE_DICTIONARY:
		return "%s: not a JSON object" % path
	return json.data


## The number of frames.
func frames() -> int:
	return _frames.size()


## The seconds the frames span: frames / fps for a loop, (frames − 1) / fps otherwise.
func duration() -> float:
	var n := _frames.size()
	return n / fps if looped else maxf(n - 1, 0) / fps


## The bytes the wind and the heights take.
func memory_bytes() -> int:
	return _frames.size() * grid.x * grid.y * 8 + _heights.size() * 4


## The wind (m/s) at `position` (metres, Godot's axes) at `time` seconds of the game's clock.
func wind_at(position: Vector3, time: float) -> Vector3:
	_moment(time)
	var v := _sample(_frames[_a], _frames[_b], _w, position)
	return Vector3(v.x, 0.0, v.y)


## `wind_at` for many positions at one time.
func wind_at_many(positions: PackedVector3Array, time: float) -> PackedVector3Array:
	_moment(time)
	var fa := _frames[_a]
	var fb := _frames[_b]
	var out := PackedVector3Array()
	out.resize(positions.size())
	for i in positions.size():
		var v := _sample(fa, fb, _w, positions[i])
		out[i] = Vector3(v.x, 0.0, v.y)
	return out


## The ground's height at (x, z): the bake's terrain where it has one, else 0; beyond the
## rectangle the edge's, or with WRAP the wrapped point's.
func ground_at(x: float, z: float) -> float:
	if _heights.is_empty():
		return 0.0
	_ground.locate(x, z, Outside.WRAP if outside == Outside.WRAP else Outside.CLAMP)
	return _ground.blend(_heights)


## The frames `t` seconds fall between, into _a, _b, _w.
func _moment(t: float) -> void:
	var n := _frames.size()
	if n <= 1:
		_a = 0
		_b = 0
		_w = 0.0
		return
	var f := t * fps
	if looped:
		f = fposmod(f, n) if is_finite(f) else 0.0
	elif is_nan(f):
		f = 0.0
	else:
		f = clampf(f, 0.0, n - 1)
	_a = mini(int(f), n - 1)
	_b = (_a + 1) % n if looped else mini(_a + 1, n - 1)
	_w = clampf(f - _a, 0.0, 1.0)


## The wind [x, z] at `p`, each corner blended between frames `fa` and `fb` by `w`.
func _sample(fa: PackedFloat32Array, fb: PackedFloat32Array, w: float, p: Vector3) -> Vector2:
	var g := _wind
	if not g.locate(p.x, p.z, outside):
		return Vector2.ZERO
	var c00 := Vector2(fa[2 * g.k00], fa[2 * g.k00 + 1]).lerp(Vector2(fb[2 * g.k00], fb[2 * g.k00 + 1]), w)
	var c10 := Vector2(fa[2 * g.k10], fa[2 * g.k10 + 1]).lerp(Vector2(fb[2 * g.k10], fb[2 * g.k10 + 1]), w)
	var c01 := Vector2(fa[2 * g.k01], fa[2 * g.k01 + 1]).lerp(Vector2(fb[2 * g.k01], fb[2 * g.k01 + 1]), w)
	var c11 := Vector2(fa[2 * g.k11], fa[2 * g.k11 + 1]).lerp(Vector2(fb[2 * g.k11], fb[2 * g.k11 + 1]), w)
	var v := c00.lerp(c10, g.fx).lerp(c01.lerp(c11, g.fx), g.fz)
	if not _law:
		return v
	var ground := 0.0
	if _heights_on_wind_grid:
		ground = g.blend(_heights)
	elif not _heights.is_empty():
		ground = ground_at(p.x, p.z)
	var h := p.y - ground
	if not (h > _z0):
		return Vector2.ZERO
	return v * (log(minf(h, _top) / _z0) / _at_reference)


# ------------------------------------------------------------------ reading a bake


## Reads the bake `m` describes from `dir`; "" or what is wrong.
func _load(dir: String, m: Dictionary) -> String:
	var where := dir.path_join("manifest.json")
	if m.get("format") != "windloom-bake":
		return "%s: format: %s, not windloom-bake" % [where, _shown(m.get("format"))]
	if _int(m.get("version"), -1) != 2:
		return "%s: version: %s; this add-on reads version 2 (bake again with this windloom)" % [where, _shown(m.get("version"))]
	sequence = _int(m.get("sequence", 0), 0)
	var fr = m.get("frames")
	if typeof(fr) != TYPE_DICTIONARY:
		return "%s: frames: not an object" % where
	var count := _int(fr.get("count"), -1)
	fps = _float(fr.get("fps"), NAN)
	looped = fr.get("loop") == true
	if count < 1 or count > MAX_FRAMES or not (fps > 0.0) or not is_finite(fps):
		return "%s: frames: %s at %s fps (1 to %d frames, a finite rate above 0)" % [where, _shown(fr.get("count")), _shown(fr.get("fps")), MAX_FRAMES]
	var entries = m.get("files")
	if typeof(entries) != TYPE_ARRAY:
		return "%s: files: not an array" % where
	for k in entries.size():
		if typeof(entries[k]) != TYPE_DICTIONARY or not _plain(entries[k].get("name")):
			return "%s: files[%d].name: %s is not a plain file name in the bake's folder" % [where, k, _shown(entries[k].get("name") if entries[k] is Dictionary else entries[k])]
	var terrain = m.get("terrain")
	if terrain != null and (typeof(terrain) != TYPE_DICTIONARY or not _plain(terrain.get("file"))):
		return "%s: terrain.file: %s is not a plain file name in the bake's folder" % [where, _shown(terrain.get("file") if terrain is Dictionary else terrain)]
	var error := _profile(where, m.get("profile"))
	if not error.is_empty():
		return error
	var picked = _pick(dir, m, count)
	if picked is String:
		return picked
	error = _read_wind(dir, m, picked, count)
	if not error.is_empty():
		return error
	if terrain != null:
		return _read_terrain(dir, terrain)
	return ""


## The log law from the manifest's profile (none: the baked wind at every height).
func _profile(where: String, p) -> String:
	if p == null:
		return ""
	if typeof(p) != TYPE_DICTIONARY:
		return "%s: profile: not an object" % where
	var z0 := _float(p.get("roughness_length"), NAN)
	var href := _float(p.get("reference_height"), NAN)
	_top = _float(p.get("top"), NAN)
	if not (is_finite(z0) and is_finite(href) and is_finite(_top)):
		return "%s: profile: a height or the roughness is not a finite number" % where
	_law = z0 > 0.0 and href > z0 and _top > 0.0
	_z0 = z0
	_at_reference = log(href / z0) if _law else 1.0
	return ""


## How precisely a file holds the wind, lower first (the runtime's order): f32, f16,
## unorm16, unorm8; a volume after a 2D file of the same sample; a resampled file last.
static func _rank(e: Dictionary) -> int:
	var sample = e.get("encoding", {}).get("sample") if e.get("encoding") is Dictionary else null
	var r: int = {"f32": 0, "f16": 2, "unorm16": 4, "unorm8": 6}.get(sample, 100)
	for a in _index(e):
		if _axis(a.get("world")) == "y" and _int(a.get("cells"), 0) > 1:
			r += 1
	if e.get("resampled_from") != null:
		r += 20
	return r


## What this add-on reads of a file: "raw", "exr", "png", "dds", or "" (FGA, VF, the atlases).
static func _kind(e: Dictionary) -> String:
	var axes = e.get("axes")
	if axes is Dictionary and axes.get("sub_images") != null:
		return ""
	var ext := str(e.get("name")).get_extension().to_lower()
	return {"f32": "raw", "exr": "exr", "png": "png", "dds": "dds"}.get(ext, "")


## Where file `name` in `dir` is read from here: "file", "imported" (an export's `.ctex`),
## or "" where it cannot be.
static func _source(dir: String, name: String, kind: String) -> String:
	var path := dir.path_join(name)
	var on_web := OS.has_feature("web")
	if FileAccess.file_exists(path) and not (kind == "exr" and on_web):
		return "file"
	if (kind == "exr" or kind == "png") and FileAccess.file_exists(path + ".import"):
		return "imported"
	return ""


## The format to read: [format, kind, entries by frame, each entry's source (`_source`)],
## or a String.
func _pick(dir: String, m: Dictionary, count: int) -> Variant:
	var groups := {}  # format → entries
	for e in m["files"]:
		var kind := _kind(e)
		if kind.is_empty():
			continue
		var key := "%s/%s" % [e.get("format"), kind]
		if not groups.has(key):
			groups[key] = []
		groups[key].append(e)
	var order := []
	for key in groups:
		var entries: Array = groups[key]
		# Every frame: one file holding them all, or one a frame.
		var whole: bool = entries.size() == 1 and entries[0].get("frame") == null
		if not whole and entries.size() == count:
			var seen := {}
			for e in entries:
				var k := _int(e.get("frame"), -1)
				if k >= 0 and k < count:
					seen[k] = true
			whole = seen.size() == count
		if whole:
			entries.sort_custom(func(a, b): return _int(a.get("frame"), 0) < _int(b.get("frame"), 0))
			order.append([_rank(entries[0]) * 2 + (0 if key.ends_with("/raw") else 1), key])
	order.sort()
	var first_missing := ""
	for o in order:
		var key: String = o[1]
		var entries: Array = groups[key]
		var kind := key.get_slice("/", key.get_slice_count("/") - 1)
		var sources := PackedStringArray()
		var missing := ""
		for e in entries:
			var s := _source(dir, e["name"], kind)
			if s.is_empty():
				missing = dir.path_join(e["name"])
				break
			sources.append(s)
		if missing.is_empty():
			return [key.get_slice("/", 0), kind, entries, sources]
		if first_missing.is_empty():
			first_missing = missing
	if not first_missing.is_empty():
		var why := "EXR cannot be read on the web; " if OS.has_feature("web") else ""
		return "%s: not there, and the manifest lists it (%sship the files of at least one format with manifest.json: raw `*.f32` reads everywhere)" % [first_missing, why]
	return "%s: no file this add-on reads (raw, exr, dds, png16 or png8, every frame)" % dir.path_join("manifest.json")


## Decodes the picked files into _frames.
func _read_wind(dir: String, m: Dictionary, picked: Array, count: int) -> String:
	format = picked[0]
	var kind: String = picked[1]
	var entries: Array = picked[2]
	var sources: PackedStringArray = picked[3]
	from_imported = "imported" in sources
	var first: Dictionary = entries[0]
	sample = str(first["encoding"].get("sample", "")) if first.get("encoding") is Dictionary else ""
	var g = _grid_of(_index(first))
	if g == null:
		return "%s: axes.index: no x and z axes of 1 to %d cells over a rectangle" % [dir.path_join(first["name"]), MAX_GRID_SIDE]
	_wind = g
	grid = Vector2i(g.nx, g.ny)
	bounds_min = g.lo
	bounds_max = g.hi
	var cells: int = g.nx * g.ny
	if count * cells * 8 > MAX_WIND_BYTES:
		return "%s: %d frames of %d × %d cells, more than the %d MiB of wind this add-on holds" % [dir.path_join(first["name"]), count, g.nx, g.ny, MAX_WIND_BYTES >> 20]
	var factors := PackedFloat32Array()
	var profile = m.get("profile")
	if profile is Dictionary and profile.get("factors") is Array:
		for f in profile["factors"]:
			factors.append(_float(f, NAN))
	_frames.clear()
	files.clear()
	for i in entries.size():
		var e: Dictionary = entries[i]
		var path := dir.path_join(e["name"])
		files.append(e["name"])
		var want := 1 if e.get("frame") != null else count
		var stored = _stored(dir, e, kind, sources[i], want * _cells(e))
		if stored is String:
			return "%s: %s" % [path, stored]
		var by_name: bool = kind == "exr" or sources[i] == "imported"
		var error := _decode(e, stored[0], stored[1], factors, want, by_name)
		if not error.is_empty():
			return "%s: %s" % [path, error]
	return ""


## The stored samples of one file: [channels a cell, PackedFloat32Array], or a String.
## `source` is where it is read from (`_source`); `cells` is what the manifest says it holds
## (frames × its axes' cells).
func _stored(dir: String, e: Dictionary, kind: String, source: String, cells: int) -> Variant:
	var path := dir.path_join(e["name"])
	var channels: int = e["encoding"]["channels"].size() if e.get("encoding") is Dictionary and e["encoding"].get("channels") is Array else 0
	if channels < 2 or channels > 4:
		return "encoding.channels: %d channels, not 2 to 4" % channels
	if cells <= 0:
		return "axes: no cells"
	if source == "imported":
		return WindloomFiles.imported(path, cells)
	# The file, exactly as long as the manifest lists it, and no longer than its cells and
	# channels can take (twice the floats, and 1 MiB more).
	var bytes := _int(e.get("bytes"), -1)
	if bytes < 0 or bytes > cells * channels * 8 + (1 << 20):
		return "bytes: %s, not a size %d cells of %d channels can take" % [_shown(e.get("bytes")), cells, channels]
	var f := FileAccess.open(path, FileAccess.READ)
	if f == null:
		return "cannot be opened (%s)" % error_string(FileAccess.get_open_error())
	if f.get_length() != bytes:
		return "%d bytes, and the manifest lists %d" % [f.get_length(), bytes]
	var data := f.get_buffer(bytes)
	if data.size() != bytes:
		return "%d bytes read of %d" % [data.size(), bytes]
	match kind:
		"raw":
			if data.size() != cells * channels * 4:
				return "%d bytes, where %d cells of %d f32 take %d" % [data.size(), cells, channels, cells * channels * 4]
			return [channels, data.to_float32_array()]
		"dds":
			return WindloomFiles.dds(data, cells)
		"png":
			return WindloomFiles.png_samples(data, Vector2i(_axis_cells(e, "x"), _axis_cells(e, "z")))
		"exr":
			if data.size() < 4 or data.decode_u32(0) != 20000630:
				return "not an EXR file"
			var image := Image.load_from_file(ProjectSettings.globalize_path(path))
			if image == null or image.is_empty():
				return "not an EXR image Godot reads"
			return WindloomFiles.image_samples(image, cells)
	return "no reader for `%s`" % kind


## One file's samples decoded by its manifest entry (`value = stored × scale + offset`, each
## channel along its world axis; the index axes as data, a volume's layer nearest the
## reference height with its factor divided out), appended to _frames.
func _decode(e: Dictionary, channels: int, stored: PackedFloat32Array, factors: PackedFloat32Array, want: int, by_name: bool) -> String:
	var cx := []
	var cz := []
	var listed: Array = e["encoding"]["channels"]
	for c in listed.size():
		var ch = listed[c]
		if not ch is Dictionary or ch.get("quantity") != "velocity":
			continue
		var axis := str(ch.get("axis", ""))
		# An image Godot decoded (as RGBA) by its channels' names, a file read here in the
		# order its channels are listed.
		var name := str(ch.get("name", ""))
		var at := "RGBA".find(name) if by_name and name.length() == 1 else c
		if at < 0 or at >= channels:
			return "encoding: channel %d (%s) is not in the file's %d channels" % [c, _shown(ch.get("name")), channels]
		var d := [at, -1.0 if axis.begins_with("-") else 1.0, _float(ch.get("scale"), NAN), _float(ch.get("offset"), NAN)]
		if not (is_finite(d[2]) and is_finite(d[3])):
			return "encoding: a channel's scale or offset is not a finite number"
		if _axis(axis) == "x":
			cx = d
		elif _axis(axis) == "z":
			cz = d
	if cx.is_empty() or cz.is_empty():
		return "encoding: no velocity channels along x and z"
	var index := _index(e)
	var nx: int = _wind.nx
	var ny: int = _wind.ny
	var layer_axis := -1
	var sizes := PackedInt64Array()
	var flips := []
	var roles := PackedStringArray()
	for a in index.size():
		var world := str(index[a].get("world", ""))
		var cells := _int(index[a].get("cells"), 0)
		var role := _axis(world)
		if (role == "x" and cells != nx) or (role == "z" and cells != ny):
			return "axes: %d cells along %s, where the bake's first file has %d × %d" % [cells, world, nx, ny]
		if role == "y" and cells > 1:
			layer_axis = a
		elif not (role == "x" or role == "y" or role == "z"):
			return "axes: an index axis along `%s`" % world
		sizes.append(cells)
		flips.append(world.begins_with("-"))
		roles.append(role)
	var layer := -1
	var up := 1.0
	if layer_axis >= 0:
		if factors.size() != sizes[layer_axis]:
			return "a volume of %d layers, and the manifest's profile has %d factors" % [sizes[layer_axis], factors.size()]
		for k in factors.size():
			if factors[k] > 0.0 and (layer < 0 or absf(log(factors[k])) < absf(log(factors[layer]))):
				layer = k
		if layer < 0:
			return "the profile's factors are all zero: no layer holds the wind"
		up = 1.0 / factors[layer]
	var per_frame := 1
	for s in sizes:
		per_frame *= s
	if stored.size() != want * per_frame * channels:
		return "%d samples, where %d frame(s) of %d cells of %d channels need %d" % [stored.size(), want, per_frame, channels, want * per_frame * channels]
	var plane := nx * ny
	var simple: bool = index.size() == 2 and roles[0] == "x" and roles[1] == "z" and not flips[0] and not flips[1]
	for frame in want:
		var v := PackedFloat32Array()
		v.resize(plane * 2)
		var base := frame * per_frame
		for flat in per_frame:
			var i := 0
			var j := 0
			if simple:
				i = flat % nx
				j = flat / nx
			else:
				var rest := flat
				var keep := true
				for a in sizes.size():
					var c: int = rest % sizes[a]
					rest /= sizes[a]
					if flips[a]:
						c = sizes[a] - 1 - c
					if roles[a] == "x":
						i = c
					elif roles[a] == "z":
						j = c
					elif a == layer_axis:
						keep = c == layer
				if not keep:
					continue
			var s := (base + flat) * channels
			var x: float = cx[1] * (stored[s + cx[0]] * cx[2] + cx[3]) * up
			var z: float = cz[1] * (stored[s + cz[0]] * cz[2] + cz[3]) * up
			if not (is_finite(x) and is_finite(z)):
				return "cell %d of frame %d decodes to (%s, %s) m/s: not a finite wind" % [j * nx + i, _frames.size(), x, z]
			v[2 * (j * nx + i)] = x
			v[2 * (j * nx + i) + 1] = z
		_frames.append(v)
	return ""


## The terrain's heights (`heights.png`, 16 bits, `height = stored × scale + offset`).
func _read_terrain(dir: String, t: Dictionary) -> String:
	var path := dir.path_join(t["file"])
	if t.get("sample") != "unorm16":
		return "%s: sample %s; heights are unorm16" % [path, _shown(t.get("sample"))]
	var scale := _float(t.get("scale"), NAN)
	var offset := _float(t.get("offset"), NAN)
	if not (is_finite(scale) and is_finite(offset)):
		return "%s: terrain: scale or offset not a finite number" % path
	var axes = t.get("axes")
	var g = _grid_of(axes if axes is Array else [])
	if g == null:
		return "%s: terrain.axes: no x and z axes" % path
	if not FileAccess.file_exists(path):
		return "%s: not there as a file (in an exported game: import it as Keep File, which the add-on's import tool does)" % path
	var f := FileAccess.open(path, FileAccess.READ)
	if f == null:
		return "%s: cannot be opened (%s)" % [path, error_string(FileAccess.get_open_error())]
	if f.get_length() > g.nx * g.ny * 8 + (1 << 20):
		return "%s: %d bytes, more than %d × %d heights can take" % [path, f.get_length(), g.nx, g.ny]
	var png = WindloomFiles.png_samples(f.get_buffer(f.get_length()), Vector2i(g.nx, g.ny))
	if png is String:
		return "%s: %s" % [path, png]
	var channels: int = png[0]
	var grey: PackedFloat32Array = png[1]
	var flip := false
	for a in axes:
		flip = flip or (a is Dictionary and a.get("world") == "-z")
	_heights = PackedFloat32Array()
	_heights.resize(g.nx * g.ny)
	for j in g.ny:
		var row: int = g.ny - 1 - j if flip else j
		for i in g.nx:
			var m: float = grey[(row * g.nx + i) * channels] * scale + offset
			if not is_finite(m):
				return "%s: a height decodes to no finite number" % path
			_heights[j * g.nx + i] = m
	_ground = g
	_heights_on_wind_grid = g.nx == _wind.nx and g.ny == _wind.ny and g.lo == _wind.lo and g.hi == _wind.hi
	return ""


# ------------------------------------------------------------------ the manifest's parts


static func _index(e: Dictionary) -> Array:
	var axes = e.get("axes")
	if axes is Dictionary and axes.get("index") is Array:
		return axes["index"].filter(func(a): return a is Dictionary)
	return []


static func _axis(world) -> String:
	return str(world).trim_prefix("+").trim_prefix("-")


static func _axis_cells(e: Dictionary, name: String) -> int:
	for a in _index(e):
		if _axis(a.get("world")) == name:
			return _int(a.get("cells"), 0)
	return 0


## The cells one frame of a file holds (the product of its axes'), 0 where that is no size.
static func _cells(e: Dictionary) -> int:
	var n := 1
	for a in _index(e):
		var c := _int(a.get("cells"), 0)
		if c < 1 or c > MAX_GRID_SIDE:
			return 0
		n *= c
	return n


## The grid of x and z index axes, or null where they do not make one within the limits.
static func _grid_of(index: Array) -> Grid:
	var x = null
	var z = null
	for a in index:
		if a is Dictionary and _axis(a.get("world")) == "x":
			x = a
		elif a is Dictionary and _axis(a.get("world")) == "z":
			z = a
	if x == null or z == null:
		return null
	var nx := _int(x.get("cells"), 0)
	var nz := _int(z.get("cells"), 0)
	var rx = x.get("range")
	var rz = z.get("range")
	if nx < 1 or nz < 1 or nx > MAX_GRID_SIDE or nz > MAX_GRID_SIDE or not (rx is Array and rz is Array and rx.size() == 2 and rz.size() == 2):
		return null
	var lo := Vector2(_float(rx[0], NAN), _float(rz[0], NAN))
	var hi := Vector2(_float(rx[1], NAN), _float(rz[1], NAN))
	if not (lo.is_finite() and hi.is_finite() and hi.x > lo.x and hi.y > lo.y):
		return null
	return Grid.new(nx, nz, lo, hi)


## A plain file name in the bake's folder: no folder, no `..`, nothing absolute, no control
## character.
static func _plain(name) -> bool:
	if typeof(name) != TYPE_STRING or name.is_empty() or name == "." or name == ".." or name.length() > 255:
		return false
	for c in name:
		if "/\\:".contains(c) or c.unicode_at(0) < 32 or c.unicode_at(0) == 127:
			return false
	return true


static func _int(v, fallback: int) -> int:
	if typeof(v) == TYPE_INT:
		return v
	if typeof(v) == TYPE_FLOAT and is_finite(v) and v == floorf(v) and absf(v) < 9.0e15:
		return int(v)
	return fallback


static func _float(v, fallback: float) -> float:
	return float(v) if typeof(v) == TYPE_INT or typeof(v) == TYPE_FLOAT else fallback


## A value from the manifest as an error shows it: its JSON, escaped and bounded.
static func _shown(v) -> String:
	return _line(JSON.stringify(v)).left(80)


## One line of at most MAX_ERROR_CHARS, its control characters escaped.
static func _line(text: String) -> String:
	var out := ""
	for c in text:
		var u := c.unicode_at(0)
		out += "\\u{%x}" % u if u < 32 or u == 127 else c
		if out.length() >= MAX_ERROR_CHARS:
			return out.left(MAX_ERROR_CHARS - 1) + "…"
	return out
