//! The wind presets blow as they are named: a storm stronger than gusts stronger than a
//! breeze, a valley wind along its valley, a swirl turning about the middle.

use super::*;
use windloom::doc::presets;

/// The layout `name`'s preset makes of a calm 100 m world.
fn with_preset(name: &str) -> Layout {
    let mut l = Layout::new(name, [100.0, 100.0], [64, 64]);
    let p = presets::wind(name, &l).unwrap();
    presets::apply_wind(&l, p).apply(&mut l).unwrap();
    l
}

fn mean_speed(s: &Solver) -> f32 {
    let v = s.velocity_field();
    v.iter().map(|w| w[0].hypot(w[1])).sum::<f32>() / v.len() as f32
}

#[test]
fn wind_presets_blow_as_named() {
    let speed = |name: &str| {
        let mut s = Solver::new(&with_preset(name));
        run(&mut s, 10.0);
        mean_speed(&s)
    };
    let (breeze, gusty, storm) = (speed("Breeze"), speed("Gusty"), speed("Storm"));
    assert!(
        breeze > 0.5 && gusty > breeze * 1.3 && storm > gusty * 1.5,
        "breeze {breeze}, gusty {gusty}, storm {storm} m/s"
    );

    // The valley wind: along x down the middle, several times its cross wind.
    let mut s = Solver::new(&with_preset("Valley wind"));
    run(&mut s, 10.0);
    let along: Vec<[f32; 2]> = (2..9)
        .map(|k| s.velocity_at([k as f32 * 10.0, 50.0]))
        .collect();
    let u = along.iter().map(|w| w[0]).sum::<f32>() / along.len() as f32;
    let v = along.iter().map(|w| w[1].abs()).sum::<f32>() / along.len() as f32;
    assert!(u > 3.0 && u > 5.0 * v, "valley: along {u}, across {v} m/s");

    // The swirl: on its ring the wind turns one way (towards increasing angle) all round.
    let mut s = Solver::new(&with_preset("Swirl"));
    run(&mut s, 10.0);
    let r = 30.0;
    for k in 0..12 {
        let a = (k as f32 + 0.5) / 12.0 * std::f32::consts::TAU;
        let w = s.velocity_at([50.0 + r * a.cos(), 50.0 + r * a.sin()]);
        let tangential = -w[0] * a.sin() + w[1] * a.cos();
        assert!(
            tangential > 0.5,
            "at {:.0}°: tangential {tangential} m/s",
            a.to_degrees()
        );
    }
}
