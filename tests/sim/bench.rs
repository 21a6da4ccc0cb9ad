//! `windloom bench`: its JSON, its split and its bound.

use super::*;

/// Runs `windloom bench --backend cpu … --json` with `args`; the output of a run that worked.
fn bench(args: &[&str]) -> std::process::Output {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(["bench", "--backend", "cpu", "--json"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// `windloom bench --json` prints one JSON object with the fields the performance record
/// needs, and its bound is the byte count over the bandwidth it measured.
#[test]
fn bench_prints_one_json_object_with_the_split_and_the_bound() {
    let out = bench(&[
        "--grid",
        "64",
        "--pressure",
        "jacobi",
        "--iterations",
        "4",
        "--steps",
        "3",
        "--warmup",
        "1",
        "--threads",
        "2",
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.trim().lines().count(), 1, "one line: {text}");
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["grid"], serde_json::json!([64, 64]));
    assert_eq!(j["iterations"], 4);
    assert_eq!(j["steps"], 3);
    assert_eq!(j["threads"], 2);
    // The obstacles layout confines vorticity, so the CPU step fuses curl, confinement and
    // divergence into one sweep and reports it as one pass.
    let passes = [
        "forces",
        "curl_confinement_divergence",
        "pressure",
        "gradient",
        "advection",
    ];
    let mut bytes = 0;
    for p in passes {
        let ms = j["passes_ms"][p].as_f64().unwrap();
        assert!(ms >= 0.0, "{p}: {ms}");
        bytes += j["passes_bytes"][p].as_u64().unwrap();
    }
    assert_eq!(j["passes_ms"].as_object().unwrap().len(), passes.len());
    assert_eq!(j["passes_bytes"].as_object().unwrap().len(), passes.len());
    assert_eq!(j["bytes_per_step"].as_u64().unwrap(), bytes);
    // The unfused pipeline's count: three passes (curl 4F + 5C, confinement 32C + 9F,
    // divergence 4F + 5C) where the fused sweep moves 9F + 9C.
    let (c, f) = (64 * 64, 2 * 65 * 64);
    let substeps = example("obstacles.json").sim.substeps.max(1) as u64;
    let unfused = j["unfused_bytes_per_step"].as_u64().unwrap();
    // The fused count also reads back the splat gains it keeps (a float per splat face),
    // which the unfused forces compute.
    let gains = j["gain_bytes_per_step"].as_u64().unwrap();
    assert!(
        gains > 0 && gains.is_multiple_of(4),
        "{gains} bytes of gains"
    );
    assert_eq!(
        unfused + gains - bytes,
        (8 * f + 33 * c) * substeps,
        "unfused {unfused}, fused {bytes}, gains {gains}"
    );
    // Pressure: 8 bytes/cell warm start + 13 bytes/cell per iteration.
    assert_eq!(j["passes_bytes"]["pressure"], 64 * 64 * (8 + 13 * 4));
    let (median, min) = (
        j["median_ms"].as_f64().unwrap(),
        j["min_ms"].as_f64().unwrap(),
    );
    assert!(min > 0.0 && min <= median, "min {min}, median {median}");
    let bw = j["bandwidth_gb_s"].as_f64().unwrap();
    let bound = j["bound_ms"].as_f64().unwrap();
    assert!(bw > 0.1, "bandwidth {bw} GB/s");
    let want = bytes as f64 / (bw * 1e9) * 1e3;
    assert!(
        (bound - want).abs() <= 1e-9 * want.max(1.0),
        "bound {bound} vs {want}"
    );
    assert!((j["ratio_to_bound"].as_f64().unwrap() - median / bound).abs() < 1e-9 * median / bound);
    let unfused_bound = j["unfused_bound_ms"].as_f64().unwrap();
    let want = unfused as f64 / (bw * 1e9) * 1e3;
    assert!((unfused_bound - want).abs() <= 1e-9 * want.max(1.0));
    let ratio = j["ratio_to_unfused_bound"].as_f64().unwrap();
    assert!((ratio - median / unfused_bound).abs() < 1e-9 * ratio);
    // The projection of a developed step cuts the divergence (4 Jacobi iterations: a little).
    let (before, after) = (
        j["divergence_before"].as_f64().unwrap(),
        j["divergence_after"].as_f64().unwrap(),
    );
    assert!(before > 0.0 && after < before, "{before} -> {after}");
    let cut = j["divergence_reduction"].as_f64().unwrap();
    assert!((cut - before / after).abs() <= 1e-3 * cut, "{cut}");

    // A level's own proportions, as `bake --grid` writes them.
    let out = bench(&["--grid", "48x32", "--steps", "1", "--warmup", "0"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["grid"], serde_json::json!([48, 32]));
}

/// `bench --layout all` runs every bundled example and prints a JSON array, one object each.
#[test]
fn bench_runs_every_example_as_a_json_array() {
    let out = bench(&[
        "--grid",
        "32",
        "--iterations",
        "2",
        "--steps",
        "1",
        "--warmup",
        "0",
        "--layout",
        "all",
    ]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = j
        .as_array()
        .expect("an array")
        .iter()
        .map(|r| r["layout"].as_str().unwrap())
        .collect();
    for name in [
        "obstacles.json",
        "meadow.json",
        "two-winds.json",
        "breeze-fft.json",
        "branching.json",
    ] {
        assert!(
            names.iter().any(|n| n.ends_with(name)),
            "{name} in {names:?}"
        );
    }
    assert!(
        j.as_array()
            .unwrap()
            .iter()
            .all(|r| r["grid"] == serde_json::json!([32, 32]))
    );
}
