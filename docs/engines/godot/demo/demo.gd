extends Node3D
## Builds the demo at run time: a field of grass blades over the baked level with
## windloom_grass.gdshader, particles carried by the wind volume with
## windloom_particles.gdshader, a camera and a sun, and a WindloomWind node that keeps both
## on the latest bake in res://wind (re-bake with `windloom bake … --watch` and watch it change).

const BAKE := "res://wind"
## Grass blades scattered over the level (fewer on a slow renderer).
@export var blades := 40000
## Particles carried by the wind volume.
@export var particles_amount := 4000


func _ready() -> void:
	var m := WindloomBake.read_manifest(BAKE)
	if m.is_empty():
		push_error("windloom demo: no bake in %s; see project.godot for the command" % BAKE)
		return
	var lo := Vector2(m["world"]["min"][0], m["world"]["min"][1])
	var hi := Vector2(m["world"]["max"][0], m["world"]["max"][1])

	var grass := ShaderMaterial.new()
	grass.shader = load("res://addons/windloom/windloom_grass.gdshader")
	var blade := _blade_mesh()
	blade.surface_set_material(0, grass)
	var multimesh := MultiMesh.new()
	multimesh.transform_format = MultiMesh.TRANSFORM_3D
	multimesh.mesh = blade
	multimesh.instance_count = blades
	var rng := RandomNumberGenerator.new()
	rng.seed = 7
	for i in blades:
		var basis := Basis(Vector3.UP, rng.randf() * TAU).scaled(Vector3.ONE * rng.randf_range(0.6, 1.0))
		var at := Vector3(rng.randf_range(lo.x, hi.x), 0.0, rng.randf_range(lo.y, hi.y))
		multimesh.set_instance_transform(i, Transform3D(basis, at))
	var field := MultiMeshInstance3D.new()
	field.multimesh = multimesh
	add_child(field)

	var wind := WindloomWind.new()
	wind.bake_dir = BAKE
	wind.grass_materials = [grass]
	if m["engines"]["godot"].has("volume"):
		var process := ShaderMaterial.new()
		process.shader = load("res://addons/windloom/windloom_particles.gdshader")
		var size: Array = m["engines"]["godot"]["volume"]["volume_size"]
		process.set_shader_parameter("emission_box", Vector3(size[0], 2.0, size[2]))
		var particles := GPUParticles3D.new()
		particles.amount = particles_amount
		particles.lifetime = 8.0
		particles.process_material = process
		var dot := SphereMesh.new()
		dot.radius = 0.05
		dot.height = 0.1
		particles.draw_pass_1 = dot
		particles.visibility_aabb = AABB(Vector3(lo.x, 0, lo.y), Vector3(size[0], size[1], size[2]))
		particles.position = Vector3((lo.x + hi.x) / 2.0, 1.5, (lo.y + hi.y) / 2.0)
		add_child(particles)
		wind.particle_materials = [process]
	add_child(wind)

	var sun := DirectionalLight3D.new()
	sun.rotation_degrees = Vector3(-50, 30, 0)
	add_child(sun)
	# The level's ground, and a sky to light it.
	var ground := MeshInstance3D.new()
	var plane := PlaneMesh.new()
	plane.size = hi - lo
	var soil := StandardMaterial3D.new()
	soil.albedo_color = Color(0.16, 0.2, 0.08)
	soil.roughness = 1.0
	plane.material = soil
	ground.mesh = plane
	ground.position = Vector3((lo.x + hi.x) / 2.0, 0.0, (lo.y + hi.y) / 2.0)
	add_child(ground)
	var sky := Sky.new()
	sky.sky_material = ProceduralSkyMaterial.new()
	var environment := Environment.new()
	environment.background_mode = Environment.BG_SKY
	environment.sky = sky
	environment.ambient_light_source = Environment.AMBIENT_SOURCE_SKY
	var world := WorldEnvironment.new()
	world.environment = environment
	add_child(world)
	# Looking over the level from its south edge, low enough to see the blades bend.
	var camera := Camera3D.new()
	var centre := Vector3((lo.x + hi.x) / 2.0, 0.0, (lo.y + hi.y) / 2.0)
	var span := (hi - lo).length()
	camera.position = Vector3(centre.x, 0.12 * span, hi.y + 0.08 * span)
	add_child(camera)
	camera.look_at(centre - Vector3(0, 0, 0.1 * span))


## A blade: a thin strip along +Y, height 1, facing +Z, in four segments so it can bend.
func _blade_mesh() -> ArrayMesh:
	var st := SurfaceTool.new()
	st.begin(Mesh.PRIMITIVE_TRIANGLES)
	var segments := 4
	for s in segments:
		var y0 := float(s) / segments
		var y1 := float(s + 1) / segments
		var w0 := 0.03 * (1.0 - y0)
		var w1 := 0.03 * (1.0 - y1)
		for v in [Vector3(-w0, y0, 0), Vector3(w0, y0, 0), Vector3(w1, y1, 0),
				Vector3(-w0, y0, 0), Vector3(w1, y1, 0), Vector3(-w1, y1, 0)]:
			st.set_normal(Vector3(0, 0, 1))
			st.add_vertex(v)
	return st.commit()
