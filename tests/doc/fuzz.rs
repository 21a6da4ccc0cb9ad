//! Fuzzing the loader (issue 13): arbitrary bytes and mutated layouts, through `validate`,
//! `render` and `bake`.

use super::*;

/// One random change to a JSON document: a value replaced (by a huge, negative, fractional or
/// non-numeric one, a string, null, a bool, an array or an object), a key removed, or an
/// unknown key added — at a path chosen by `pick`.
fn mutate(v: &mut serde_json::Value, pick: &[u32], kind: u32, n: f64) {
    use serde_json::Value as V;
    // The path first (reading), then one mutable borrow of the place it names.
    let mut pointer = String::new();
    let mut cur = &*v;
    for &p in pick {
        let next = match cur {
            V::Object(m) if !m.is_empty() => {
                let (k, x) = m.iter().nth(p as usize % m.len()).unwrap();
                pointer += &format!("/{}", k.replace('~', "~0").replace('/', "~1"));
                Some(x)
            }
            V::Array(a) if !a.is_empty() => {
                let i = p as usize % a.len();
                pointer += &format!("/{i}");
                Some(&a[i])
            }
            _ => None,
        };
        match next {
            Some(n) => cur = n,
            None => break,
        }
    }
    let at = v.pointer_mut(&pointer).unwrap();
    // Half the changes only nudge a number (a plausible edit that keeps the type), so mutants
    // reach the validator's ranges and the solver, not only the type checks.
    if kind % 20 >= 10
        && let Some(x) = at.as_f64()
    {
        let nudged = x * (1.0 + n / 1e6);
        *at = if at.is_u64() && nudged >= 0.0 {
            serde_json::json!(nudged.round() as u64)
        } else {
            serde_json::json!(nudged)
        };
        return;
    }
    let replacement = match kind % 10 {
        0 => serde_json::json!(n),
        1 => serde_json::json!(-n),
        2 => serde_json::json!(1e300),
        3 => serde_json::json!("NaN"),
        4 => V::Null,
        5 => V::Bool(true),
        6 => serde_json::json!([n, n, n]),
        7 => serde_json::json!({"unexpected": n}),
        8 => {
            if let V::Object(m) = at {
                if let Some(k) = m.keys().next().cloned() {
                    m.remove(&k);
                }
                return;
            }
            V::Null
        }
        _ => {
            if let V::Object(m) = at {
                m.insert("surprise".into(), serde_json::json!(n));
                return;
            }
            serde_json::json!(n.fract())
        }
    };
    *at = replacement;
}

fn fuzz_base() -> serde_json::Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
    // A grid small enough that every accepted mutant is stepped.
    v["world"]["grid"] = serde_json::json!([48, 48]);
    v
}

/// The mutations reach both sides: over 2,000 seeded mutants, some are refused and some
/// accepted (and stepped), so the property above tests both paths. Also how the file's numbers
/// in docs/RELIABILITY.md were taken.
#[test]
fn fuzz_mutants_reach_both_refusal_and_acceptance() {
    let (mut ok, mut refused) = (0, 0);
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) as u32
    };
    for _ in 0..2000 {
        let mut v = fuzz_base();
        for _ in 0..1 + next() % 3 {
            let pick: Vec<u32> = (0..1 + next() % 5).map(|_| next()).collect();
            let kind = next();
            let n = f64::from(next() % 2_000_000) - 1e6;
            mutate(&mut v, &pick, kind, n);
        }
        match doc::parse(&serde_json::to_string_pretty(&v).unwrap()) {
            Ok(l) => {
                ok += 1;
                let mut s = windloom::sim::Solver::new(&l);
                for _ in 0..5 {
                    s.step();
                }
                assert!(s.u.iter().chain(&s.v).all(|x| x.is_finite()));
            }
            Err(_) => refused += 1,
        }
    }
    println!("2000 mutants: {ok} accepted and stepped, {refused} refused");
    assert!(
        ok >= 100 && refused >= 100,
        "{ok} accepted, {refused} refused"
    );
}

/// What every rejection must look like: at least one diagnostic, each with a 1-based
/// position inside the text and a message.
fn check_rejection(text: &str, d: &doc::Diagnostics) -> Result<(), TestCaseError> {
    prop_assert!(!d.0.is_empty());
    let lines = text.lines().count().max(1);
    for x in &d.0 {
        prop_assert!(x.line >= 1 && x.line <= lines + 1, "{x} in {lines} lines");
        prop_assert!(x.column >= 1);
        prop_assert!(!x.message.is_empty());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Arbitrary bytes: the loader never panics, and every rejection names a position.
    #[test]
    fn arbitrary_bytes_are_refused_cleanly(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Err(d) = doc::parse(&text) {
            check_rejection(&text, &d)?;
        }
    }

    /// A real layout with one to three random changes: refused with positioned diagnostics, or
    /// accepted as a layout the validator passes, that serialises back to what it parses, and
    /// that the solver steps without a non-finite value (grids up to 128² stepped).
    #[test]
    fn mutated_layouts_are_refused_cleanly_or_run(
        changes in proptest::collection::vec(
            (proptest::collection::vec(any::<u32>(), 1..6), any::<u32>(), -1e6f64..1e6),
            1..4,
        ),
    ) {
        let mut v = fuzz_base();
        for (pick, kind, n) in &changes {
            mutate(&mut v, pick, *kind, *n);
        }
        let text = serde_json::to_string_pretty(&v).unwrap();
        match doc::parse(&text) {
            Err(d) => check_rejection(&text, &d)?,
            Ok(l) => {
                prop_assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
                let again = doc::parse(&doc::to_json(&l)).expect("its own JSON parses");
                prop_assert_eq!(&again, &l);
                if l.world.grid[0] * l.world.grid[1] <= 128 * 128 {
                    let mut s = windloom::sim::Solver::new(&l);
                    for _ in 0..10 {
                        s.step();
                    }
                    prop_assert!(s.u.iter().chain(&s.v).all(|x| x.is_finite()));
                }
            }
        }
    }
}

/// Every example, its grid shrunk so a mutant renders and bakes quickly, and the folder its
/// backdrop path is relative to.
fn fuzz_example(which: usize) -> (serde_json::Value, PathBuf) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    let names = [
        "meadow.json",
        "branching.json",
        "breeze-fft.json",
        "obstacles.json",
        "two-winds.json",
    ];
    let text = std::fs::read_to_string(dir.join(names[which % names.len()])).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["world"]["grid"] = serde_json::json!([40, 32]);
    (v, dir)
}

proptest! {
    // About a quarter of the mutants are accepted: some 40 renders and bakes a run.
    #![proptest_config(ProptestConfig::with_cases(160))]

    /// Mutants of every example through what users run on a layout: `render` (a top-down
    /// picture) and a short `bake` into every format. Each accepted mutant either yields a
    /// PNG and a complete bake (every file the manifest lists, non-empty), or a refusal with
    /// a message that leaves no output folder; nothing panics.
    #[test]
    fn mutated_layouts_render_and_bake_or_refuse_cleanly(
        which in 0usize..5,
        changes in proptest::collection::vec(
            // Mostly nudged numbers (kinds 10..20), so most mutants are accepted and reach
            // the renderer and the bake; any other change now and then.
            (
                proptest::collection::vec(any::<u32>(), 1..6),
                prop_oneof![3 => 10u32..20, 1 => any::<u32>()],
                -1e6f64..1e6,
            ),
            1..3,
        ),
    ) {
        let (mut v, base) = fuzz_example(which);
        for (pick, kind, n) in &changes {
            mutate(&mut v, pick, *kind, *n);
        }
        let Ok(l) = doc::parse(&serde_json::to_string_pretty(&v).unwrap()) else {
            return Ok(()); // refusals: the property above
        };
        if l.world.grid[0] * l.world.grid[1] <= 64 * 64 {
            match windloom::render::render_png(&l, &base, [96, 64], 0.2, None) {
                Ok(png) => prop_assert!(png.starts_with(b"\x89PNG\r\n\x1a\n")),
                Err(e) => prop_assert!(!e.to_string().is_empty()),
            }
        }
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("bake");
        let opts = windloom::bake::BakeOptions {
            warmup: 0.1,
            frames: 2,
            fps: 10.0,
            grid: Some([24, 16]),
            ..Default::default()
        };
        let cancel = std::sync::atomic::AtomicBool::new(false);
        match windloom::bake::bake(&l, &out, &opts, &cancel, &mut |_, _, _| {}) {
            Ok(m) => {
                prop_assert!(!m.files.is_empty());
                for f in &m.files {
                    let len = std::fs::metadata(out.join(&f.name)).map(|m| m.len()).unwrap_or(0);
                    prop_assert!(len > 0, "{} missing or empty", f.name);
                }
                prop_assert!(out.join("manifest.json").exists());
            }
            Err(e) => {
                prop_assert!(!e.to_string().is_empty());
                prop_assert!(!out.exists(), "a refused bake leaves nothing: {e}");
            }
        }
    }
}
