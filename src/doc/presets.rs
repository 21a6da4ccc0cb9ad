//! Presets: the wind (ambient layers, and for a valley or a swirl an arrow tree, sized to the
//! world) and the grass (its blades and colours), each applied as one edit. A user's own
//! preset is a layout (read and written by `io::presets`): a wind preset its ambient layers
//! and trees, a grass preset its grass.

use super::clipboard;
use super::edit::Edit;
use super::types::*;

/// The wind presets that ship with windloom.
pub const WIND: [&str; 5] = ["Breeze", "Gusty", "Storm", "Valley wind", "Swirl"];
/// The grass presets that ship with windloom.
pub const GRASS: [&str; 4] = ["Lawn", "Meadow", "Wheat", "Tall grass"];

fn layer(name: &str, kind: AmbientKind) -> AmbientLayer {
    AmbientLayer::new(0, name, kind)
}

fn directional(
    main: f32,
    turbulence: f32,
    pulse_magnitude: f32,
    pulse_frequency: f32,
) -> AmbientKind {
    AmbientKind::Directional {
        direction_deg: 0.0,
        main,
        turbulence,
        pulse_magnitude,
        pulse_frequency,
    }
}

fn tree(name: &str, points: &[Vec2], strength: f32, radius: f32) -> Tree {
    let chain = super::stroke::chain(
        points,
        super::stroke::StrokeSettings { strength, radius },
        1,
    )
    .expect("a preset's tree has two points or more");
    Tree {
        id: 0,
        name: name.into(),
        enabled: true,
        window: TimeWindow::Always,
        emission: Emission::Continuous,
        propagation_speed: 20.0,
        locked: false,
        hidden: false,
        root: chain,
        keys: Vec::new(),
    }
}

/// Built-in wind preset `name` for a world of `layout`'s size: a layout holding its ambient
/// layers and trees. `None` for a name not in [`WIND`].
pub fn wind(name: &str, layout: &Layout) -> Option<Layout> {
    let (lo, hi) = layout.bounds();
    let size = layout.world.size;
    let short = size[0].min(size[1]);
    let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let mut out = Layout::new(name, size, layout.world.grid);
    out.world.origin = layout.world.origin;
    // A gust's size: a fifth of the world, within what reads as gusts (5 to 60 m).
    let gusts = (short / 5.0).clamp(5.0, 60.0);
    match name {
        "Breeze" => out.ambient = vec![layer("Breeze", directional(2.5, 0.6, 0.25, 0.15))],
        "Gusty" => {
            out.ambient = vec![
                layer("Gusty wind", directional(4.0, 1.2, 0.8, 0.25)),
                layer(
                    "Gusts",
                    AmbientKind::Noise {
                        direction_deg: 0.0,
                        scale: gusts,
                        speed: 6.0,
                        strength: 3.0,
                    },
                ),
            ]
        }
        "Storm" => {
            out.ambient = vec![
                layer("Storm", directional(12.0, 3.0, 0.9, 0.4)),
                layer(
                    "Storm gusts",
                    AmbientKind::Fft {
                        direction_deg: 0.0,
                        wind_speed: 12.0,
                        amplitude: 4.0,
                        resolution: 64,
                        tile_size: (short / 2.0).clamp(8.0, 256.0),
                        seed: 7,
                    },
                ),
            ]
        }
        "Valley wind" => {
            // Down the world's long axis through its middle, with a light breeze along it.
            let along_x = size[0] >= size[1];
            let points: Vec<Vec2> = (0..5)
                .map(|k| {
                    let t = 0.1 + 0.2 * k as f32;
                    if along_x {
                        [lo[0] + t * size[0], mid[1]]
                    } else {
                        [mid[0], lo[1] + t * size[1]]
                    }
                })
                .collect();
            let mut breeze = directional(1.5, 0.3, 0.1, 0.1);
            if let AmbientKind::Directional { direction_deg, .. } = &mut breeze {
                *direction_deg = if along_x { 0.0 } else { 90.0 };
            }
            out.ambient = vec![layer("Valley breeze", breeze)];
            out.trees = vec![tree("Valley wind", &points, 6.0, short / 8.0)];
        }
        "Swirl" => {
            // A ring of arrows round the middle, nearly closed: the wind turns about it.
            let r = short * 0.3;
            let points: Vec<Vec2> = (0..=10)
                .map(|k| {
                    let a = k as f32 / 11.0 * std::f32::consts::TAU;
                    [
                        mid[0] + r * crate::num::cos(a),
                        mid[1] + r * crate::num::sin(a),
                    ]
                })
                .collect();
            out.trees = vec![tree("Swirl", &points, 6.0, r / 3.0)];
        }
        _ => return None,
    }
    Some(out)
}

/// Built-in grass preset `name`. `None` for a name not in [`GRASS`].
pub fn grass(name: &str) -> Option<GrassParams> {
    let palette = |name: &str, base: [f32; 3], tip: [f32; 3]| Palette {
        name: name.into(),
        base,
        tip,
    };
    let meadow = GrassParams::default();
    Some(match name {
        "Lawn" => GrassParams {
            density: 400.0,
            height: [0.06, 0.12],
            width: [0.01, 0.02],
            stiffness: [2.0, 3.0],
            k1: 0.02,
            k2: 0.05,
            lambda: 0.6,
            palettes: vec![palette("lawn", [0.05, 0.20, 0.04], [0.30, 0.60, 0.15])],
            ..meadow
        },
        "Meadow" => meadow,
        "Wheat" => GrassParams {
            density: 150.0,
            height: [0.8, 1.1],
            width: [0.01, 0.02],
            stiffness: [1.0, 1.5],
            k1: 0.03,
            k2: 0.08,
            lambda: 0.35,
            palettes: vec![
                palette("wheat", [0.45, 0.38, 0.12], [0.90, 0.78, 0.40]),
                palette("ripe", [0.50, 0.40, 0.15], [0.85, 0.65, 0.30]),
            ],
            ..meadow
        },
        "Tall grass" => GrassParams {
            density: 80.0,
            height: [0.8, 1.5],
            width: [0.03, 0.06],
            stiffness: [0.4, 1.0],
            k1: 0.08,
            k2: 0.15,
            lambda: 0.15,
            palettes: vec![
                palette("tall", [0.08, 0.20, 0.05], [0.50, 0.62, 0.22]),
                palette("seed heads", [0.22, 0.25, 0.08], [0.70, 0.66, 0.38]),
            ],
            ..meadow
        },
        _ => return None,
    })
}

/// The edit that applies wind preset `preset` (a layout, built in or a user's) to `layout`:
/// the preset's ambient layers replace the layout's, and its trees are added, placed in
/// `layout`'s world as they were in the preset's (positions stretched from one world
/// rectangle to the other, radii by the mean stretch). One undo step.
pub fn apply_wind(layout: &Layout, mut preset: Layout) -> Edit {
    let (from_lo, _) = preset.bounds();
    let (to_lo, _) = layout.bounds();
    let sx = layout.world.size[0] / preset.world.size[0];
    let sz = layout.world.size[1] / preset.world.size[1];
    let sr = (sx * sz).sqrt();
    for t in &mut preset.trees {
        fn place(n: &mut Node, f: &dyn Fn(Vec2) -> Vec2, sr: f32) {
            n.pos = f(n.pos);
            n.radius = super::bounds::RADIUS.clamp(n.radius * sr);
            for c in &mut n.children {
                place(c, f, sr);
            }
        }
        let f = |p: Vec2| {
            [
                to_lo[0] + (p[0] - from_lo[0]) * sx,
                to_lo[1] + (p[1] - from_lo[1]) * sz,
            ]
        };
        place(&mut t.root, &f, sr);
    }
    preset.obstacles.clear();
    let mut edits: Vec<Edit> = (layout.ambient.iter())
        .map(|a| Edit::RemoveAmbient { id: a.id })
        .collect();
    preset.world = layout.world.clone();
    if let Some(pasted) = clipboard::paste(layout, preset, [0.0, 0.0]) {
        edits.push(pasted.edit);
    }
    Edit::Named("Apply wind preset", Box::new(Edit::Batch(edits)))
}

/// The edit that applies grass preset `preset` to `layout`: its blades and colours, keeping
/// the layout's density map and seed. One undo step.
pub fn apply_grass(layout: &Layout, preset: GrassParams) -> Edit {
    let grass = Edit::SetGrass(GrassParams {
        density_map: layout.grass.density_map.clone(),
        seed: layout.grass.seed,
        ..preset
    });
    Edit::Named("Apply grass preset", Box::new(grass))
}

/// A wind preset of `layout`: its ambient layers and the trees `trees` names (all of them
/// when it names none), in its world.
pub fn wind_of(layout: &Layout, trees: &[u32]) -> Layout {
    let mut out = Layout::new(&layout.name, layout.world.size, layout.world.grid);
    out.world.origin = layout.world.origin;
    out.ambient = layout.ambient.clone();
    out.trees = (layout.trees.iter())
        .filter(|t| trees.is_empty() || trees.contains(&t.id))
        .cloned()
        .collect();
    out
}

/// A grass preset of `layout`: its grass, without the density map (a level's own image).
pub fn grass_of(layout: &Layout) -> Layout {
    let mut out = Layout::new(&layout.name, layout.world.size, layout.world.grid);
    out.grass = GrassParams {
        density_map: None,
        ..layout.grass.clone()
    };
    out
}
