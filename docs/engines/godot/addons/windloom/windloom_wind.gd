@tool
class_name WindloomWind
extends Node
## Keeps grass and particle materials on the latest bake in `bake_dir`: it polls the
## manifest's `sequence` and, when it changed (a re-bake by `windloom bake --watch` or the
## editor's Live export), loads the textures and sets the materials' uniforms. It reads the
## manifest, then the files, then the manifest again, and keeps what it read only when the
## sequence held, so it never shows half of one bake and half of another. A bake whose
## files fail to load is reported (`bake_failed`, `last_error`) and the last good bake stays
## on show. An animated volume plays frame by frame, blended, at the bake's fps.
## Works in the editor, in an exported game and on the web (see WindloomBake).
##
## Gameplay asks it for the wind at a point: `wind_at(position, time)` and `wind_at_many`
## answer from the same bake, on the CPU, by windloom's runtime rules (WindloomField), and
## follow re-bakes with the materials.

@export_dir var bake_dir := "res://wind"
## Materials using windloom_grass.gdshader (or windloom_wind.gdshaderinc).
@export var grass_materials: Array[ShaderMaterial] = []
## Process materials using windloom_particles.gdshader (or windloom_volume.gdshaderinc).
@export var particle_materials: Array[ShaderMaterial] = []
@export var poll_seconds := 0.5
## Keep the bake's wind on the CPU for `wind_at` (frames × cells × 8 bytes: 14.7 MB for 48
## frames of 240 × 160). Off: only the materials are set, and `wind_at` answers zero.
@export var gameplay_wind := true
## What `wind_at` answers beyond the baked rectangle: the edge's wind, none, or the bake
## repeated (for levels simulated with periodic edges).
@export var outside: WindloomField.Outside = WindloomField.Outside.CLAMP:
	set(value):
		outside = value
		if field != null:
			field.outside = value

## The sequence of the bake on show (-1: none yet).
var sequence := -1
## What failed in the last bake that could not be loaded ("" when the last load worked).
var last_error := ""
## The wind on the CPU of the bake on show (null: none, or `gameplay_wind` off).
var field: WindloomField
## The volume frames on show and their playback.
var volumes: Array[Texture3D] = []
var volume_fps := 24.0
var volume_loops := true
## Seconds of volume playback.
var clock := 0.0
var _waited := 0.0
var _failed_sequence := -1
var _warned_no_wind := false

signal bake_loaded(sequence: int)
signal bake_failed(sequence: int, message: String)


func _ready() -> void:
	reload_if_changed()


func _process(delta: float) -> void:
	clock += delta
	_play_volume()
	_waited += delta
	if _waited < poll_seconds:
		return
	_waited = 0.0
	reload_if_changed()


## Loads the bake when its sequence changed; whether it did.
func reload_if_changed() -> bool:
	var m := WindloomBake.read_manifest(bake_dir)
	if m.is_empty():
		return false
	var seq := int(m.get("sequence", 0))
	if seq == sequence or seq == _failed_sequence:
		return false
	var error := ""
	var grass: Array[ShaderMaterial] = []
	for material in grass_materials:
		var copy := material.duplicate() as ShaderMaterial
		error = WindloomBake.apply_grass(copy, bake_dir, m)
		if not error.is_empty():
			break
		grass.append(copy)
	var new_volumes: Array[Texture3D] = []
	if error.is_empty() and not particle_materials.is_empty():
		var loaded = WindloomBake.load_volumes(bake_dir, m)
		if loaded is String:
			error = loaded
		else:
			new_volumes = loaded
	var new_field: WindloomField = null
	if error.is_empty() and gameplay_wind and not WindloomField.holds_wind(m):
		# Not a broken bake: one for shaders alone (atlases). The materials load; wind_at
		# answers zero and says why once.
		if not _warned_no_wind:
			push_warning("windloom: bake %d in %s holds no files wind_at reads (raw, exr, dds, png16, png8): wind_at answers zero; bake --format raw too" % [seq, bake_dir])
			_warned_no_wind = true
	elif error.is_empty() and gameplay_wind:
		var opened = WindloomField.open(bake_dir, m, outside)
		if opened is String:
			error = opened
		else:
			new_field = opened
	var again := WindloomBake.read_manifest(bake_dir)
	if int(again.get("sequence", -1)) != seq:
		return false  # a bake landed while reading: try again at the next poll
	if not error.is_empty():
		_failed_sequence = seq
		last_error = error
		var kept := "keeping bake %d" % sequence if sequence >= 0 else "no bake on show"
		push_error("windloom: bake %d in %s could not be loaded: %s; %s" % [seq, bake_dir, error, kept])
		bake_failed.emit(seq, error)
		return false
	_copy_uniforms(grass, grass_materials)
	field = new_field
	volumes = new_volumes
	if not volumes.is_empty():
		for material in particle_materials:
			WindloomBake.apply_particles(material, m, volumes)
		volume_fps = float(m["frames"]["fps"])
		volume_loops = bool(m["frames"].get("loop", true))
		_play_volume()
	sequence = seq
	last_error = ""
	bake_loaded.emit(sequence)
	return true


## The wind (m/s, Godot's axes) at `position` (metres, the level's coordinates as the
## bake has them: put this node's level at the origin, or subtract its origin) at `time`
## seconds of the game's clock (a float: 64 bits, so a clock weeks on reads as precisely as
## one just started). Bilinear between cells, linear between frames (looping or holding as
## the bake says), carried up and down by the bake's log-law profile above its terrain;
## `outside` beyond the rectangle. Zero while no bake is loaded.
func wind_at(position: Vector3, time: float) -> Vector3:
	return field.wind_at(position, time) if field != null else Vector3.ZERO


## `wind_at` for many positions at one time (a flock, a row of flags).
func wind_at_many(positions: PackedVector3Array, time: float) -> PackedVector3Array:
	if field != null:
		return field.wind_at_many(positions, time)
	var zero := PackedVector3Array()
	zero.resize(positions.size())
	return zero


## The ground's height at (x, z) as the bake has it (0 without terrain).
func ground_at(x: float, z: float) -> float:
	return field.ground_at(x, z) if field != null else 0.0


## The volume frame pair and blend at `clock`: frame k = floor(clock · fps), looping or
## holding the last frame as the bake says.
func _play_volume() -> void:
	if volumes.size() < 2:
		return
	var n := volumes.size()
	var t := clock * volume_fps
	var k := int(floor(t))
	var blend := t - k
	var a := posmod(k, n) if volume_loops else mini(k, n - 1)
	var b := posmod(k + 1, n) if volume_loops else mini(k + 1, n - 1)
	for material in particle_materials:
		material.set_shader_parameter("wind_volume", volumes[a])
		material.set_shader_parameter("wind_volume_next", volumes[b])
		material.set_shader_parameter("volume_blend", blend)


func _copy_uniforms(from: Array[ShaderMaterial], to: Array[ShaderMaterial]) -> void:
	for i in to.size():
		for u in to[i].shader.get_shader_uniform_list():
			to[i].set_shader_parameter(u["name"], from[i].get_shader_parameter(u["name"]))
