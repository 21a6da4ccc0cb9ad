@tool
extends EditorPlugin
## Project → Tools → "windloom: import bake…": pick a bake folder inside the project; its
## textures get the `.import` settings the manifest names and are reimported.

const MENU := "windloom: import bake…"


func _enter_tree() -> void:
	add_tool_menu_item(MENU, _choose_folder)


func _exit_tree() -> void:
	remove_tool_menu_item(MENU)


func _choose_folder() -> void:
	var dialog := EditorFileDialog.new()
	dialog.file_mode = EditorFileDialog.FILE_MODE_OPEN_DIR
	dialog.access = EditorFileDialog.ACCESS_RESOURCES
	dialog.dir_selected.connect(import_bake)
	dialog.close_requested.connect(dialog.queue_free)
	EditorInterface.get_base_control().add_child(dialog)
	dialog.popup_file_dialog()


## Writes the import settings of the bake in `dir` (a res:// folder) and reimports it.
func import_bake(dir: String) -> void:
	var m := WindloomBake.read_manifest(dir)
	if m.is_empty():
		push_error("windloom: %s holds no windloom manifest.json" % dir)
		return
	var paths := WindloomBake.write_import_settings(dir, m)
	var fs := EditorInterface.get_resource_filesystem()
	fs.scan()
	fs.reimport_files(paths)
	print("windloom: imported %d textures of bake %d from %s" % [paths.size(), int(m["sequence"]), dir])
