//! The engine-side scripts in docs/engines/ run against a bake: the Unreal import script under
//! Python with a stand-in `unreal` module that records what it asks of the editor
//! (`stubs/unreal.py`, limited to the names Unreal's Python API documents).

use super::*;
use serde_json::Value;

/// Runs `code` under python3 with the Unreal script and the stand-in on its path; its last
/// line of output as JSON. `None` (and a loud note) where there is no python3.
fn python(code: &str) -> Option<Value> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = format!(
        "{}:{}",
        root.join("tests/export/stubs").display(),
        root.join("docs/engines/unreal").display()
    );
    let out = match std::process::Command::new("python3")
        .env("PYTHONPATH", path)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .args(["-c", code])
        .output()
    {
        Ok(o) => o,
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("SKIPPED: no python3 to run the Unreal script ({e})");
            return None;
        }
        Err(e) => panic!("CI needs python3: {e}"),
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_str(stdout.lines().last().unwrap()).unwrap())
}

/// `windloom_import.py` imports every file of `engines.unreal` into the content folder and
/// gives each asset exactly the settings the manifest names, then saves them.
#[test]
fn the_unreal_script_imports_with_the_manifest_s_settings() {
    let dir = tempfile::tempdir().unwrap();
    let m = run(&example("obstacles.json"), dir.path(), &small(2));
    let json = manifest(dir.path());
    let code = format!(
        "import json, unreal, windloom_import as w\n\
         done = w.import_bake({:?}, '/Game/Wind')\n\
         print(json.dumps({{'calls': unreal.calls, 'sequence': done[1], 'files': sorted(done[0])}}))",
        dir.path().display().to_string()
    );
    let Some(out) = python(&code) else { return };
    assert_eq!(out["sequence"], m.sequence);
    let ue = &json["engines"]["unreal"];
    let calls = out["calls"].as_array().unwrap();
    let set = |file: &str, property: &str| -> Vec<Value> {
        calls
            .iter()
            .filter(|c| c[0] == "set" && c[1] == file && c[2] == property)
            .map(|c| c[3].clone())
            .collect()
    };
    let mut expected = Vec::new();
    for f in ue["vector_field_static"]["files"].as_array().unwrap() {
        let f = f.as_str().unwrap();
        assert_eq!(
            set(f, "intensity"),
            [ue["vector_field_static"]["intensity"].clone()]
        );
        expected.push(f.to_string());
    }
    let texture = |f: &str, s: &Value| {
        assert_eq!(
            set(f, "compression_settings"),
            [Value::from(format!(
                "TextureCompressionSettings.{}",
                s["compression_settings"].as_str().unwrap()
            ))]
        );
        assert_eq!(set(f, "srgb"), [s["srgb"].clone()]);
        assert_eq!(
            set(f, "address_x"),
            [Value::from(format!(
                "TextureAddress.{}",
                s["address_x"].as_str().unwrap()
            ))]
        );
        assert_eq!(
            set(f, "mip_gen_settings"),
            [Value::from("TextureMipGenSettings.TMGS_NO_MIPMAPS")]
        );
    };
    texture("atlas.png", &ue["niagara_atlas"]["texture"]);
    expected.push("atlas.png".into());
    for f in ue["material_texture"]["files"].as_array().unwrap() {
        texture(f.as_str().unwrap(), &ue["material_texture"]["texture"]);
        expected.push(f.as_str().unwrap().into());
    }
    for f in ue["volume_texture"]["files"].as_array().unwrap() {
        let f = f.as_str().unwrap();
        assert_eq!(
            set(f, "compression_settings"),
            [Value::from("TextureCompressionSettings.TC_HDR_F32")]
        );
        assert_eq!(
            set(f, "address_mode"),
            [Value::from("TextureAddress.TA_CLAMP")]
        );
        expected.push(f.into());
    }
    expected.sort();
    assert_eq!(out["files"], serde_json::json!(expected));
    // Every file its own asset: the EXR and the FGA of one frame share a stem (the stand-in
    // refuses a second import onto one path, as Unreal would replace the first asset).
    let paths: std::collections::BTreeSet<&str> = calls
        .iter()
        .filter(|c| c[0] == "import")
        .map(|c| c[5].as_str().unwrap())
        .collect();
    assert_eq!(
        paths.len(),
        expected.len(),
        "one asset path per file: {paths:?}"
    );
    assert!(
        paths.contains("/Game/Wind/wind_0000_exr") && paths.contains("/Game/Wind/wind_0000_fga")
    );
    for f in &expected {
        assert!(
            calls.iter().any(|c| c[0] == "import"
                && c[1] == f.as_str()
                && c[2] == "/Game/Wind"
                && c[3] == true),
            "{f} imported, replacing"
        );
        assert!(
            calls.iter().any(|c| c[0] == "save" && c[1] == f.as_str()),
            "{f} saved"
        );
    }
}

/// The script's live link: it imports on the first tick, not again while the sequence stays,
/// and again after a re-bake.
#[test]
fn the_unreal_script_reimports_when_the_sequence_changes() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("meadow.json");
    let opts = BakeOptions {
        formats: vec![Format::Fga],
        ..small(1)
    };
    run(&layout, dir.path(), &opts);
    let d = dir.path().display().to_string();
    let first = format!(
        "import json, unreal, windloom_import as w\n\
         w.watch({d:?}, '/Game/Wind')\n\
         tick = unreal._ticks[0]\n\
         for _ in range(4): tick(0.3)\n\
         print(json.dumps(sum(1 for c in unreal.calls if c[0] == 'import')))"
    );
    let Some(imports) = python(&first) else {
        return;
    };
    assert_eq!(imports, 1, "one import while the bake stays");
    // A second process, after a re-bake: two sequences, two imports.
    let second = format!(
        "import json, subprocess, unreal, windloom_import as w\n\
         w.watch({d:?}, '/Game/Wind')\n\
         tick = unreal._ticks[0]\n\
         tick(0.6)\n\
         subprocess.run([{bin:?}, 'bake', {layout:?}, '--out', {d:?}, '--format', 'fga', '--grid', '24x16', '--warmup', '0'], check=True, capture_output=True)\n\
         tick(0.6)\n\
         tick(0.6)\n\
         print(json.dumps([c[1] for c in unreal.calls if c[0] == 'log']))",
        bin = env!("CARGO_BIN_EXE_windloom"),
        layout = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("layouts/meadow.json")
            .display()
            .to_string(),
    );
    let Some(logs) = python(&second) else { return };
    assert_eq!(
        logs,
        serde_json::json!([
            format!("windloom: imported bake 1 from {d}"),
            format!("windloom: imported bake 2 from {d}")
        ])
    );
}

/// Every key of every object in `v`.
fn keys(v: &Value, out: &mut BTreeSet<String>) {
    match v {
        Value::Object(o) => {
            for (k, v) in o {
                out.insert(k.clone());
                keys(v, out);
            }
        }
        Value::Array(a) => a.iter().for_each(|v| keys(v, out)),
        _ => {}
    }
}

/// The strings between each `open` and the next `close` in `text`.
fn between<'a>(text: &'a str, open: &str, close: &str) -> Vec<&'a str> {
    let mut found = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(open) {
        rest = &rest[at + open.len()..];
        if let Some(end) = rest.find(close) {
            found.push(&rest[..end]);
            rest = &rest[end..];
        }
    }
    found
}

fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

/// The Godot add-on, the Unity scripts and the Unreal script read the manifest by the names
/// a bake of every format writes, and the Godot scripts set only uniforms its shaders declare:
/// a misspelt key or uniform fails here rather than silently in an engine.
#[test]
fn the_engine_scripts_read_the_manifest_s_own_names() {
    let dir = tempfile::tempdir().unwrap();
    run(
        &example("obstacles.json"),
        dir.path(),
        &BakeOptions {
            grid: Some([24, 16]),
            ..small(2)
        },
    );
    let mut known = BTreeSet::new();
    keys(&manifest(dir.path()), &mut known);
    // A terrain bake's keys too (`terrain`, its file and axes), and a resampled FGA's.
    let terrain = tempfile::tempdir().unwrap();
    run(
        &example("walled-garden.json"),
        terrain.path(),
        &BakeOptions {
            grid: Some([160, 100]),
            formats: vec![Format::Raw, Format::Fga],
            ..small(1)
        },
    );
    keys(&manifest(terrain.path()), &mut known);
    let godot = [
        "docs/engines/godot/addons/windloom/windloom_bake.gd",
        "docs/engines/godot/addons/windloom/windloom_field.gd",
        "docs/engines/godot/addons/windloom/windloom_wind.gd",
        "docs/engines/godot/addons/windloom/windloom_plugin.gd",
        "docs/engines/godot/demo/demo.gd",
    ];
    let python = ["docs/engines/unreal/windloom_import.py"];
    let mut checked = 0;
    for path in godot.iter().chain(&python) {
        let text = read(path);
        for key in between(&text, "[\"", "\"]")
            .into_iter()
            .chain(between(&text, ".get(\"", "\""))
            .chain(between(&text, ".has(\"", "\""))
        {
            assert!(
                known.contains(key),
                "{path} reads {key:?}, which no manifest holds"
            );
            checked += 1;
        }
    }
    // Unity's JsonUtility reads by field name: each field of the manifest classes.
    for path in [
        "docs/engines/unity/Editor/WindloomImport.cs",
        "docs/engines/unity/Runtime/WindloomVectorField.cs",
    ] {
        let text = read(path);
        for class in between(&text, "[Serializable]", "}") {
            for field in between(class, "public ", ";") {
                let name = field.split_whitespace().last().unwrap();
                assert!(
                    known.contains(name),
                    "{path} reads {name:?}, which no manifest holds"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 40, "{checked} names checked");
    // Uniforms the Godot scripts set are the shaders' own (the wind's are in the includes).
    let shaders = read("docs/engines/godot/addons/windloom/windloom_grass.gdshader")
        + &read("docs/engines/godot/addons/windloom/windloom_particles.gdshader")
        + &read("docs/engines/godot/addons/windloom/windloom_wind.gdshaderinc")
        + &read("docs/engines/godot/addons/windloom/windloom_volume.gdshaderinc");
    let uniforms: BTreeSet<&str> = shaders
        .lines()
        .filter_map(|l| l.trim().strip_prefix("uniform "))
        .filter_map(|l| l.split([' ', ':', '=', ';']).nth(1))
        .collect();
    for path in godot {
        for name in between(&read(path), "set_shader_parameter(\"", "\"") {
            assert!(
                uniforms.contains(name),
                "{path} sets {name:?}, no shader uniform"
            );
        }
    }
    // And the manifest's shader parameters are the grass shader's uniforms.
    for key in manifest(dir.path())["engines"]["godot"]["shader_parameters"]
        .as_object()
        .unwrap()
        .keys()
    {
        assert!(uniforms.contains(key.as_str()), "{key} is no uniform");
    }
}
