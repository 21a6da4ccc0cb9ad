//! `windloom probe`: the wind at points over time, as CSV a reader takes back, with the
//! statistics a designer reads; bad flags refused without writing anything.

use super::*;
use windloom::engine::probe::{self, Reading};

fn windloom(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn probe_writes_every_reading_as_csv_matching_the_solver() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("probes.csv");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let o = windloom(&[
        "probe",
        layout.to_str().unwrap(),
        "--at",
        "40,60",
        "--at",
        "90,30",
        "--warmup",
        "2",
        "--seconds",
        "3",
        "--hz",
        "10",
        "--csv",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The CSV, read back by a CSV reader: a header, then 30 rows, 10 a second after the
    // warm-up.
    let mut r = csv::Reader::from_path(&out).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header[0], "time_s");
    assert_eq!(header[1], "40,60 speed_mps");
    assert_eq!(header.len(), 1 + 2 * 4);
    let rows: Vec<Vec<f32>> = r
        .records()
        .map(|rec| rec.unwrap().iter().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 30);
    assert!((rows[0][0] - 2.0).abs() < 0.05 && (rows[29][0] - 4.9).abs() < 0.05);
    for row in &rows {
        // Speed and direction agree with the components.
        let (s, d, x, z) = (row[1], row[2], row[3], row[4]);
        assert!((s - x.hypot(z)).abs() < 1e-3);
        assert!((d - z.atan2(x).to_degrees().rem_euclid(360.0)).abs() < 0.05 || s < 1e-3);
    }
    // The last row is the solver's wind there at that time (bilinear between faces, within
    // what the cell-centred reading smooths).
    let l = example("obstacles.json");
    let mut s = windloom::sim::Solver::new(&l);
    let steps = (rows[29][0] / l.sim.dt).round() as usize;
    for _ in 0..steps {
        s.step();
    }
    let w = s.velocity_at([40.0, 60.0]);
    let peak = w[0].hypot(w[1]).max(1.0);
    assert!(
        (rows[29][3] - w[0]).abs() < 0.05 * peak && (rows[29][4] - w[1]).abs() < 0.05 * peak,
        "{:?} vs {w:?}",
        &rows[29][3..5]
    );
    // The summary: one line per probe, min ≤ mean ≤ max, a gust factor of at least 1.
    let lines: Vec<&str> = stdout.lines().skip(1).collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    let nums: Vec<f32> = lines[0]
        .rsplitn(6, ", ")
        .take(5)
        .map(|x| x.parse().unwrap())
        .collect();
    let (dir_deg, gust, max, mean, min) = (nums[0], nums[1], nums[2], nums[3], nums[4]);
    assert!(min <= mean && mean <= max && gust >= 1.0 && (0.0..=360.0).contains(&dir_deg));
    // West gale at (40, 60) blows east, a strong wind.
    assert!(mean > 5.0 && !(60.0..300.0).contains(&dir_deg), "{stdout}");
}

#[test]
fn probe_refuses_bad_requests_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("keep.csv");
    std::fs::write(&out, "mine").unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let l = layout.to_str().unwrap();
    let o = out.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &["probe", l, "--at", "400,60", "--csv", o],
            "400,60 lies outside the world",
        ),
        (&["probe", l, "--csv", o], "nothing to measure"),
        (&["probe", l, "--at", "4,x", "--csv", o], "expected X,Z"),
        (
            &["probe", l, "--at", "4,4", "--seconds", "0", "--csv", o],
            "--seconds must be",
        ),
        (
            &["probe", l, "--at", "4,4", "--hz", "1000", "--csv", o],
            "--hz must be",
        ),
    ];
    for (args, says) in cases {
        let r = windloom(args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{args:?}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine", "{args:?}");
    }
    // A folder where the CSV should go is refused.
    let r = windloom(&[
        "probe",
        l,
        "--at",
        "4,4",
        "--seconds",
        "0.5",
        "--csv",
        dir.path().to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("is a folder"));
}

#[test]
fn the_layout_s_probes_are_read_when_no_point_is_given() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = example("two-winds.json");
    l.probes.push(windloom::doc::Probe {
        id: 900,
        name: "Banner, north".into(),
        pos: [50.0, 30.0],
    });
    let path = dir.path().join("l.json");
    windloom::io::save(&path, &l).unwrap();
    let csv_path = dir.path().join("p.csv");
    let o = windloom(&[
        "probe",
        path.to_str().unwrap(),
        "--warmup",
        "0",
        "--seconds",
        "1",
        "--csv",
        csv_path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut r = csv::Reader::from_path(&csv_path).unwrap();
    // A name with a comma is quoted, and reads back whole.
    assert_eq!(&r.headers().unwrap()[1], "Banner, north speed_mps");
}

#[test]
fn gusts_and_direction_read_as_a_designer_expects() {
    let steady: Vec<Reading> = (0..600)
        .map(|k| Reading {
            time: k as f32 * 0.05,
            wind: [0.0, -4.0],
        })
        .collect();
    let s = probe::stats(&steady).unwrap();
    assert_eq!((s.min, s.mean, s.max), (4.0, 4.0, 4.0));
    assert!((s.gust_factor - 1.0).abs() < 1e-5);
    assert!((s.mean_direction_deg - 270.0).abs() < 1e-3, "north is 270°");
    // 30 s at 4 m/s with one 3-second gust at 8 m/s: the gust factor is 8 over the mean.
    let gusty: Vec<Reading> = (0..600)
        .map(|k| {
            let t = k as f32 * 0.05;
            let v = if (10.0..13.0).contains(&t) { 8.0 } else { 4.0 };
            Reading {
                time: t,
                wind: [v, 0.0],
            }
        })
        .collect();
    let s = probe::stats(&gusty).unwrap();
    let mean = (4.0 * 540.0 + 8.0 * 60.0) / 600.0;
    assert!((s.mean - mean).abs() < 1e-3);
    assert!(
        (s.gust_factor - 8.0 / mean).abs() < 0.02,
        "{}",
        s.gust_factor
    );
    // A one-reading spike of a gust does not make a 3-second gust.
    let mut spike = steady.clone();
    spike[300].wind = [0.0, -40.0];
    let s = probe::stats(&spike).unwrap();
    assert_eq!(s.max, 40.0);
    assert!(s.gust_factor < 1.2, "{}", s.gust_factor);
    assert!(probe::stats(&[]).is_none());
}

/// A reading every step (`--hz` the step's rate, 60 at the examples' `dt` of 1/60) is taken:
/// it was refused as "at most 60, got 60", `1 / dt` in f32 being a hair under 60.
#[test]
fn a_reading_every_step_is_taken() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("every-step.csv");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let l = example("obstacles.json");
    let hz = (1.0 / l.sim.dt).round();
    let o = windloom(&[
        "probe",
        layout.to_str().unwrap(),
        "--at",
        "40,60",
        "--warmup",
        "0",
        "--seconds",
        "0.5",
        "--hz",
        &hz.to_string(),
        "--csv",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = csv::Reader::from_path(&out).unwrap().records().count();
    assert_eq!(rows as f32, (0.5 * hz).round(), "one reading a step");
}

/// One clock: a probe of two-winds, run on the bake's grid and step from the same warm-up,
/// reads at the bake's frame times the bake's wind, within the CSV's rounding (4 decimals).
/// The probe kept its own clock (steps × dt in f32, the first reading a step late) and the
/// bake another (the step count in f64): they differed by 0.028 m/s, 0.084 m/s just after
/// an arrow switched on.
#[test]
fn a_probe_reads_the_bake_s_wind_at_the_frames_times() {
    let dir = tempfile::tempdir().unwrap();
    let bake_dir = dir.path().join("bake");
    let m = run(
        &example("two-winds.json"),
        &bake_dir,
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(5)
        },
    );
    let [nx, ny] = m.grid;
    let raw = f32s(&std::fs::read(bake_dir.join("wind.f32")).unwrap());
    // The layout as the bake ran it: its grid and its step.
    let mut l = example("two-winds.json");
    l.world.grid = [nx as u32, ny as u32];
    l.sim.dt = m.frames.sim_dt;
    let layout = dir.path().join("as-baked.json");
    windloom::io::save(&layout, &l).unwrap();
    let cells = [(5usize, 7usize), (24, 16), (40, 3), (13, 29)];
    let mut args: Vec<String> = vec!["probe".into(), layout.display().to_string()];
    for &(i, j) in &cells {
        let x = m.world.min[0] + (i as f32 + 0.5) * m.world.cell_size[0];
        let z = m.world.min[1] + (j as f32 + 0.5) * m.world.cell_size[1];
        args.extend(["--at".into(), format!("{x},{z}")]);
    }
    let out = dir.path().join("probe.csv");
    args.extend([
        "--warmup".into(),
        format!("{:.9}", m.frames.warmup_seconds),
        "--seconds".into(),
        format!("{:.9}", m.frames.count as f32 / m.frames.fps),
        "--hz".into(),
        m.frames.fps.to_string(),
        "--csv".into(),
        out.display().to_string(),
    ]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = windloom(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: Vec<Vec<f64>> = csv::Reader::from_path(&out)
        .unwrap()
        .records()
        .map(|r| r.unwrap().iter().map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), m.frames.count, "a reading a frame");
    let mut worst = 0.0f64;
    for (k, row) in rows.iter().enumerate() {
        let t = m.frames.warmup_seconds + k as f64 / f64::from(m.frames.fps);
        assert!(
            (row[0] - t).abs() <= 5e-5,
            "reading {k} at {} s, frame at {t} s",
            row[0]
        );
        for (p, &(i, j)) in cells.iter().enumerate() {
            let c = ((k * ny + j) * nx + i) * 2;
            let (bx, bz) = (f64::from(raw[c]), f64::from(raw[c + 1]));
            let (px, pz) = (row[1 + 4 * p + 2], row[1 + 4 * p + 3]);
            worst = worst.max((px - bx).abs()).max((pz - bz).abs());
            assert!(
                (px - bx).abs() <= 6e-5 && (pz - bz).abs() <= 6e-5,
                "frame {k} cell ({i}, {j}): probe ({px}, {pz}), bake ({bx}, {bz})"
            );
        }
    }
    eprintln!("worst difference {worst:.2e} m/s");
}
