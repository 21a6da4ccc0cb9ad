//! The manifest as an engine script reads it: valid against `docs/manifest.schema.json`, and
//! enough, with no knowledge of the formats beyond how to read their samples, to turn every
//! file of a bake back into the world's wind (`value = stored × scale + offset` per channel,
//! index axes mapped to the world's by data).

use super::*;
use serde_json::Value;
use std::sync::OnceLock;

/// Fails with every schema error when `m` is not a valid manifest.
pub(crate) fn check_schema(m: &Value) {
    static VALIDATOR: OnceLock<jsonschema::Validator> = OnceLock::new();
    let v = VALIDATOR
        .get_or_init(|| jsonschema::validator_for(&bake::manifest_schema()).expect("a schema"));
    let errors: Vec<String> = v
        .iter_errors(m)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "manifest.json breaks its schema:\n{}",
        errors.join("\n")
    );
}

#[test]
fn manifest_schema_file_is_up_to_date() {
    let want = serde_json::to_string_pretty(&bake::manifest_schema()).unwrap() + "\n";
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/manifest.schema.json");
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/manifest.schema.json is out of date: run `UPDATE_SCHEMA=1 cargo test --test export schema`"
    );
    // The CLI prints the same schema.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(["schema", "--manifest"])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap(), want);
}

/// The schema refuses what an engine script could not read: a missing channel scale, an
/// unknown axis, a stray field.
#[test]
fn the_schema_refuses_a_broken_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Png8, Format::Vf],
        ..small(1)
    };
    run(&example("meadow.json"), dir.path(), &opts);
    let good = manifest(dir.path());
    let v = jsonschema::validator_for(&bake::manifest_schema()).unwrap();
    assert!(v.is_valid(&good));
    let mut broken = Vec::new();
    let mut m = good.clone();
    m["files"][0]["encoding"]["channels"][0]
        .as_object_mut()
        .unwrap()
        .remove("scale");
    broken.push(m);
    let mut m = good.clone();
    m["files"][0]["axes"]["index"][0]["world"] = "x".into();
    broken.push(m);
    let mut m = good.clone();
    m["files"][0]["encoding"]["decode"] = "prose".into();
    broken.push(m);
    let mut m = good.clone();
    m["engines"]["unity"]["vector_field"]["box_size"] = serde_json::json!([1, 2]);
    broken.push(m);
    for m in broken {
        assert!(!v.is_valid(&m), "the schema took {m}");
    }
}

/// A file's samples, one `Vec` per cell in the file's index order (fastest axis first), one
/// value per channel; per frame for a file holding several.
fn samples(dir: &Path, entry: &Value) -> Vec<Vec<Vec<f64>>> {
    let path = dir.join(entry["name"].as_str().unwrap());
    let bytes = std::fs::read(&path).unwrap();
    let channels = entry["encoding"]["channels"].as_array().unwrap().len();
    let name = entry["name"].as_str().unwrap();
    let format = match entry["format"].as_str().unwrap() {
        "dds" if name.ends_with(".exr") => "exr",
        "dds" if name.ends_with(".vf") => "vf",
        "dds" => "dds",
        other => other,
    };
    match format {
        "dds" => {
            assert_eq!(&bytes[..4], b"DDS ");
            let floats: Vec<f64> = if entry["encoding"]["sample"] == "f16" {
                bytes[148..]
                    .chunks_exact(2)
                    .map(|c| f64::from(half::f16::from_le_bytes([c[0], c[1]]).to_f32()))
                    .collect()
            } else {
                f32s(&bytes[148..]).into_iter().map(f64::from).collect()
            };
            vec![floats.chunks_exact(channels).map(|c| c.to_vec()).collect()]
        }
        "exr" | "atlas-exr" => {
            use exr::prelude::*;
            let image = read_all_flat_layers_from_file(&path).unwrap();
            let layer = &image.layer_data[0];
            let width = layer.size.width();
            let list = &layer.channel_data.list;
            let by_name: Vec<Vec<f32>> = entry["encoding"]["channels"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| {
                    let name = c["name"].as_str().unwrap();
                    let ch = list.iter().find(|l| l.name.to_string() == name).unwrap();
                    ch.sample_data.values_as_f32().collect()
                })
                .collect();
            let n = by_name[0].len();
            let pixel = |k: usize| {
                by_name
                    .iter()
                    .map(|c| f64::from(c[k]))
                    .collect::<Vec<f64>>()
            };
            let Some(sub) = entry["axes"].get("sub_images") else {
                return vec![(0..n).map(pixel).collect()];
            };
            // An atlas: each frame's sub-image, row by row.
            let (w, h) = (
                entry["grid"][0].as_u64().unwrap() as usize,
                entry["grid"][1].as_u64().unwrap() as usize,
            );
            let columns = sub["columns"].as_u64().unwrap() as usize;
            (0..sub["count"].as_u64().unwrap() as usize)
                .map(|k| {
                    let (ox, oy) = ((k % columns) * w, (k / columns) * h);
                    (0..h)
                        .flat_map(|y| (0..w).map(move |x| (x, y)))
                        .map(|(x, y)| pixel((oy + y) * width + ox + x))
                        .collect()
                })
                .collect()
        }
        "png8" | "png16" | "atlas" => {
            let max = if entry["encoding"]["sample"] == "unorm8" {
                255.0
            } else {
                65535.0
            };
            let img = image::load_from_memory(&bytes).unwrap();
            let img16 = img.to_rgb16();
            let widen = if max == 255.0 { 257.0 } else { 1.0 };
            let (w, h) = (
                entry["grid"][0].as_u64().unwrap() as u32,
                entry["grid"][1].as_u64().unwrap() as u32,
            );
            let (columns, frames) = match entry["axes"].get("sub_images") {
                Some(s) => (
                    s["columns"].as_u64().unwrap() as u32,
                    s["count"].as_u64().unwrap() as u32,
                ),
                None => (1, 1),
            };
            (0..frames)
                .map(|k| {
                    let (ox, oy) = ((k % columns) * w, (k / columns) * h);
                    (0..h)
                        .flat_map(|y| (0..w).map(move |x| (x, y)))
                        .map(|(x, y)| {
                            let p = img16.get_pixel(ox + x, oy + y);
                            (0..channels)
                                .map(|c| f64::from(p[c]) / widen / max)
                                .collect()
                        })
                        .collect()
                })
                .collect()
        }
        "vf" => {
            assert_eq!(&bytes[..4], b"VF_V");
            let floats = f32s(&bytes[10..]);
            vec![
                floats
                    .chunks_exact(3)
                    .map(|c| c.iter().map(|&v| f64::from(v)).collect())
                    .collect(),
            ]
        }
        "fga" => {
            let text = String::from_utf8(bytes).unwrap();
            let numbers: Vec<f64> = text.split(',').map(|t| t.trim().parse().unwrap()).collect();
            vec![numbers[9..].chunks_exact(3).map(|c| c.to_vec()).collect()]
        }
        "raw" => {
            let floats = f32s(&bytes);
            let per = entry["grid"][0].as_u64().unwrap() as usize
                * entry["grid"][1].as_u64().unwrap() as usize
                * 2;
            floats
                .chunks_exact(per)
                .map(|f| {
                    f.chunks_exact(2)
                        .map(|c| c.iter().map(|&v| f64::from(v)).collect())
                        .collect()
                })
                .collect()
        }
        other => panic!("no reader for {other}"),
    }
}

/// Decodes every file of the bake in `dir` by its manifest alone and compares each cell with
/// the bake's raw frames (area-averaged to the file's grid where it was resampled), within
/// the rounding of the file's sample type. Returns how many values it checked.
fn decode_by_manifest(dir: &Path) -> usize {
    let m = manifest(dir);
    let raw = Raw::read(dir, &m);
    let frames: Vec<bake::Field> = (0..m["frames"]["count"].as_u64().unwrap() as usize)
        .map(|k| bake::Field {
            nx: raw.nx,
            ny: raw.ny,
            data: (0..raw.ny)
                .flat_map(|j| (0..raw.nx).map(move |i| (i, j)))
                .map(|(i, j)| raw.at(k, i, j))
                .collect(),
        })
        .collect();
    let mut checked = 0;
    for entry in m["files"].as_array().unwrap() {
        let name = entry["name"].as_str().unwrap();
        let channels = entry["encoding"]["channels"].as_array().unwrap();
        let index = entry["axes"]["index"].as_array().unwrap();
        let cells: Vec<usize> = index
            .iter()
            .map(|a| a["cells"].as_u64().unwrap() as usize)
            .collect();
        let (fx, fy) = (
            entry["grid"][0].as_u64().unwrap() as usize,
            entry["grid"][1].as_u64().unwrap() as usize,
        );
        let per_frame = samples(dir, entry);
        // A volume's layers: the simulated wind times the profile's factor.
        let factors: Vec<f64> = m["profile"]["factors"]
            .as_array()
            .map(|f| f.iter().map(|v| v.as_f64().unwrap()).collect())
            .unwrap_or_default();
        for (n, cell_values) in per_frame.iter().enumerate() {
            let frame = entry["frame"].as_u64().map_or(n, |f| f as usize);
            let want = frames[frame].resample(fx, fy);
            assert_eq!(cell_values.len(), cells.iter().product::<usize>(), "{name}");
            for (flat, stored) in cell_values.iter().enumerate() {
                // The file's index per axis, then the grid cell by the axes' data.
                let (mut rest, mut i, mut j, mut layer) = (flat, None, None, None);
                for (a, axis) in index.iter().enumerate() {
                    let c = rest % cells[a];
                    rest /= cells[a];
                    let w = axis["world"].as_str().unwrap();
                    let g = if w.starts_with('+') {
                        c
                    } else {
                        cells[a] - 1 - c
                    };
                    match &w[1..] {
                        "x" => i = Some(g),
                        "z" => j = Some(g),
                        "y" if cells[a] == 1 => {}
                        "y" => {
                            assert_eq!(cells[a], factors.len(), "{name}: a layer per factor");
                            layer = Some(g);
                        }
                        _ => panic!("{name}: axis {w}"),
                    }
                }
                let v = want.at(i.unwrap(), j.unwrap());
                let up = layer.map_or(1.0, |k| factors[k]);
                let (vx, vz) = (f64::from(v[0]) * up, f64::from(v[1]) * up);
                for (c, ch) in channels.iter().enumerate() {
                    let scale = ch["scale"].as_f64().unwrap();
                    let value = stored[c] * scale + ch["offset"].as_f64().unwrap();
                    let expected = match (ch["quantity"].as_str().unwrap(), ch["axis"].as_str()) {
                        ("velocity", Some("+x")) => vx,
                        ("velocity", Some("-x")) => -vx,
                        ("velocity", Some("+z")) => vz,
                        ("velocity", Some("-z")) => -vz,
                        ("velocity", Some("+y" | "-y")) => 0.0,
                        ("speed", None) => vx.hypot(vz),
                        ("unused", None) => 0.0,
                        other => panic!("{name}: channel {other:?}"),
                    };
                    let tol = match entry["encoding"]["sample"].as_str().unwrap() {
                        "unorm8" => scale.abs() / 255.0 * 0.51,
                        "unorm16" => scale.abs() / 65535.0 * 0.51,
                        "f16" => 1e-3 * expected.abs() + 1e-6,
                        "f32" | "text" => 2e-6 * (expected.abs() + 1.0),
                        other => panic!("{name}: sample {other}"),
                    };
                    assert!(
                        (value - expected).abs() <= tol,
                        "{name} frame {frame} cell ({}, {}) channel {}: decoded {value}, baked {expected} (± {tol})",
                        i.unwrap(),
                        j.unwrap(),
                        ch["name"]
                    );
                    checked += 1;
                }
            }
        }
    }
    checked
}

/// Every file of every format, plain, flipped and in half floats, decodes to the bake's wind
/// by the manifest's numbers alone; the FGA of a grid over 128 cells too (area-averaged).
#[test]
fn every_file_decodes_to_the_wind_by_its_manifest_alone() {
    for (layout, opts) in [
        ("two-winds.json", small(3)),
        (
            "branching.json",
            BakeOptions {
                flip_green: true,
                half: true,
                ..small(2)
            },
        ),
        (
            "obstacles.json",
            BakeOptions {
                grid: Some([150, 60]),
                ..small(1)
            },
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let m = run(&example(layout), dir.path(), &opts);
        let formats: BTreeSet<Format> = m.files.iter().map(|f| f.format).collect();
        assert_eq!(formats.len(), Format::ALL.len(), "{layout}: every format");
        let checked = decode_by_manifest(dir.path());
        let (nx, ny) = (m.grid[0], m.grid[1]);
        assert!(checked > 10 * nx * ny, "{layout}: {checked} values checked");
    }
}

/// The engines block names the files each engine imports and the numbers its guide quotes.
#[test]
fn the_engines_block_matches_the_bake() {
    let dir = tempfile::tempdir().unwrap();
    let m = run(&example("obstacles.json"), dir.path(), &small(4));
    let json = manifest(dir.path());
    let e = &json["engines"];
    let names = |format: Format| -> Vec<String> {
        m.files
            .iter()
            .filter(|f| f.format == format)
            .map(|f| f.name.clone())
            .collect()
    };
    let (min, max) = (m.world.min, m.world.max);
    let vf = &e["unity"]["vector_field"];
    assert_eq!(vf["files"], serde_json::json!(names(Format::Vf)));
    assert_eq!(vf["data_encoding"], "Signed");
    assert_eq!(vf["import"]["wrap_mode"], "Clamp");
    assert_eq!(
        vf["box_size"],
        serde_json::json!([max[0] - min[0], 1.0, max[1] - min[1]])
    );
    let unreal = &e["unreal"];
    assert_eq!(
        unreal["vector_field_static"]["files"],
        serde_json::json!(names(Format::Fga))
    );
    assert_eq!(unreal["niagara_atlas"]["file"], "atlas.png");
    assert_eq!(
        unreal["niagara_atlas"]["texture"]["compression_settings"],
        "TC_HDR"
    );
    assert_eq!(unreal["niagara_atlas"]["frames"], 4);
    assert_eq!(
        unreal["niagara_atlas"]["atlas_size"],
        serde_json::json!([2 * m.grid[0], 2 * m.grid[1]])
    );
    let godot = &e["godot"];
    assert_eq!(godot["import"]["detect_3d/compress_to"], 0);
    assert_eq!(godot["import"]["compress/mode"], 0);
    let shader = &godot["shader_parameters"];
    assert_eq!(shader["bounds_min"], serde_json::json!(min));
    assert_eq!(shader["bounds_max"], serde_json::json!(max));
    assert_eq!(shader["use_atlas"], true);
    assert_eq!(shader["atlas_frames"], 4);
    // The float atlas where the bake has it (Godot reads it at full precision).
    assert_eq!(shader["wind_atlas"], "atlas.exr");
    assert_eq!(shader["atlas_is_float"], true);
    assert_eq!(shader["atlas_scale"], 1.0);
    assert_eq!(
        unreal["niagara_atlas"]["scale"].as_f64().unwrap() as f32,
        m.max_speed
    );
    // A bake with no file an engine reads has no block for it.
    let dir = tempfile::tempdir().unwrap();
    run(
        &example("obstacles.json"),
        dir.path(),
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(1)
        },
    );
    let e = &manifest(dir.path())["engines"];
    assert!(
        e.get("unity").is_none() && e.get("unreal").is_none() && e.get("godot").is_none(),
        "{e}"
    );
}
