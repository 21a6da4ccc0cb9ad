@tool
class_name WindloomWind
extends Node
## Keeps grass and particle materials on the latest bake in `bake_dir`: it polls the
## manifest's `sequence` and, when it changed (a re-bake by `windloom bake --watch` or the
## editor's Live export), loads the textures and sets the materials' uniforms. It reads the
## manifest, then the files, then the manifest again, and keeps what it read only when the
## sequence held, so it never shows half of one bake and half of another. Works in the
## editor and in a running game.

@export_dir var bake_dir := "res://wind"
## Materials using windloom_grass.gdshader.
@export var grass_materials: Array[ShaderMaterial] = []
## Process materials using windloom_particles.gdshader.
@export var particle_materials: Array[ShaderMaterial] = []
@export var poll_seconds := 0.5

## The sequence of the bake on show (-1: none yet).
var sequence := -1
var _waited := 0.0

signal bake_loaded(sequence: int)


func _ready() -> void:
	reload_if_changed()


func _process(delta: float) -> void:
	_waited += delta
	if _waited < poll_seconds:
		return
	_waited = 0.0
	reload_if_changed()


## Loads the bake when its sequence changed; whether it did.
func reload_if_changed() -> bool:
	var m := WindloomBake.read_manifest(bake_dir)
	if m.is_empty() or int(m.get("sequence", 0)) == sequence:
		return false
	var grass: Array[ShaderMaterial] = []
	for material in grass_materials:
		var copy := material.duplicate() as ShaderMaterial
		WindloomBake.apply_grass(copy, bake_dir, m)
		grass.append(copy)
	var particles: Array[ShaderMaterial] = []
	for material in particle_materials:
		var copy := material.duplicate() as ShaderMaterial
		WindloomBake.apply_particles(copy, bake_dir, m)
		particles.append(copy)
	var again := WindloomBake.read_manifest(bake_dir)
	if again.get("sequence", -1) != m.get("sequence", -2):
		return false  # a bake landed while reading: try again at the next poll
	_copy_uniforms(grass, grass_materials)
	_copy_uniforms(particles, particle_materials)
	sequence = int(m["sequence"])
	bake_loaded.emit(sequence)
	return true


func _copy_uniforms(from: Array[ShaderMaterial], to: Array[ShaderMaterial]) -> void:
	for i in to.size():
		for u in to[i].shader.get_shader_uniform_list():
			to[i].set_shader_parameter(u["name"], from[i].get_shader_parameter(u["name"]))
