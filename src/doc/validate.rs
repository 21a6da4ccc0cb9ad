//! Semantic validation of a [`Layout`]: every problem, each with the JSON path of its field.

use super::bounds::{self, *};
use super::types::*;
use std::collections::HashMap;
use std::fmt;

/// One semantic problem: the JSON path of the field and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Issue {
    /// e.g. `trees[1].root.children[0].radius`
    pub path: String,
    pub message: String,
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Bytes the solver needs for an `nx × ny` grid with the given pressure solve.
pub fn grid_memory(grid: [u32; 2], pressure: PressureSolve) -> u64 {
    let per_cell = match pressure {
        PressureSolve::Jacobi => SOLVER_BYTES_PER_CELL,
        PressureSolve::Multigrid => SOLVER_BYTES_PER_CELL + MULTIGRID_BYTES_PER_CELL,
    };
    u64::from(grid[0]) * u64::from(grid[1]) * per_cell
}

/// A number as a person reads it: `0.5`, `-120`, but `3e38` and `1e-40` rather than forty
/// digits.
fn num(v: f32) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

fn mib(bytes: u64) -> String {
    format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0))
}

struct Checker {
    issues: Vec<Issue>,
}

impl Checker {
    fn push(&mut self, path: &str, message: impl Into<String>) {
        self.issues.push(Issue {
            path: path.to_string(),
            message: message.into(),
        });
    }

    /// Finite and within `[lo, hi]`.
    fn range(&mut self, path: &str, v: f32, lo: f32, hi: f32) -> bool {
        if !v.is_finite() {
            self.push(path, format!("must be a finite number, got {}", num(v)));
            false
        } else if v < lo || v > hi {
            self.push(
                path,
                format!(
                    "must be between {} and {}, got {}",
                    num(lo),
                    num(hi),
                    num(v)
                ),
            );
            false
        } else {
            true
        }
    }

    /// Finite, strictly positive, at least `lo` and at most `hi`.
    fn positive_from(&mut self, path: &str, v: f32, lo: f32, hi: f32) -> bool {
        if !v.is_finite() {
            self.push(path, format!("must be a finite number, got {}", num(v)));
            false
        } else if v <= 0.0 {
            self.push(path, format!("must be > 0, got {}", num(v)));
            false
        } else if v < lo {
            self.push(
                path,
                format!("must be at least {}, got {}", num(lo), num(v)),
            );
            false
        } else if v > hi {
            self.push(path, format!("must be at most {}, got {}", num(hi), num(v)));
            false
        } else {
            true
        }
    }

    /// Within `b` (finite, and above zero where `b` says so).
    fn bound(&mut self, path: &str, v: f32, b: Bound) -> bool {
        if b.above_zero {
            self.positive_from(path, v, b.min as f32, b.hi())
        } else {
            self.range(path, v, b.min as f32, b.hi())
        }
    }

    /// A whole number within `b`.
    fn whole(&mut self, path: &str, v: u32, b: Count) -> bool {
        if b.contains(v) {
            return true;
        }
        self.push(
            path,
            format!("must be between {} and {}, got {v}", b.min, b.max),
        );
        false
    }

    fn finite(&mut self, path: &str, v: f32) -> bool {
        self.range(path, v, f32::MIN, f32::MAX)
    }

    /// A position: each coordinate within ±[`COORD_MAX`].
    fn point(&mut self, path: &str, p: Vec2) -> bool {
        let a = self.bound(&format!("{path}[0]"), p[0], COORD);
        let b = self.bound(&format!("{path}[1]"), p[1], COORD);
        a && b
    }

    /// An image's placement rectangle `[[x0, z0], [x1, z1]]`, if it has one.
    fn placement(&mut self, path: &str, rect: &Option<[Vec2; 2]>) {
        if let Some([a, b]) = rect {
            let lo = self.point(&format!("{path}[0]"), *a);
            let hi = self.point(&format!("{path}[1]"), *b);
            if lo && hi && !(a[0] < b[0] && a[1] < b[1]) {
                self.push(
                    path,
                    format!("[[x0, z0], [x1, z1]] needs x0 < x1 and z0 < z1, got [{a:?}, {b:?}]"),
                );
            }
        }
    }

    /// A `[min, max]` range, each end within `b`.
    fn min_max(&mut self, path: &str, r: Vec2, b: Bound) {
        let a = self.bound(&format!("{path}[0]"), r[0], b);
        let b = self.bound(&format!("{path}[1]"), r[1], b);
        if a && b && r[0] > r[1] {
            self.push(path, format!("min {} is larger than max {}", r[0], r[1]));
        }
    }

    /// A list of at most `max` items.
    fn count(&mut self, path: &str, n: usize, max: usize, what: &str) {
        if n > max {
            self.push(path, format!("at most {max} {what}, got {n}"));
        }
    }

    /// A name of at most [`NAME_MAX`] characters.
    fn name(&mut self, path: &str, name: &str) {
        let n = name.chars().count();
        if n > NAME_MAX {
            self.push(
                path,
                format!("a name of at most {NAME_MAX} characters, got {n}"),
            );
        }
    }

    fn unique_id(&mut self, seen: &mut HashMap<u32, String>, what: &str, id: u32, path: &str) {
        if let Some(first) = seen.get(&id) {
            self.push(
                &format!("{path}.id"),
                format!("duplicate {what} id {id} (already used by {first})"),
            );
        } else {
            seen.insert(id, path.to_string());
        }
    }
}

/// Checks a parsed layout; returns every problem found (empty when valid).
pub fn validate(layout: &Layout) -> Vec<Issue> {
    let mut c = Checker { issues: Vec::new() };
    if layout.format != FORMAT {
        c.push(
            "format",
            format!("must be \"{FORMAT}\", got \"{}\"", layout.format),
        );
    }
    if layout.version != VERSION {
        c.push(
            "version",
            format!("must be {VERSION} once loaded, got {}", layout.version),
        );
    }
    check_world(&mut c, &layout.world, layout.sim.pressure);
    c.name("name", &layout.name);
    c.count("trees", layout.trees.len(), TREES_MAX, "wind trees");
    c.count(
        "obstacles",
        layout.obstacles.len(),
        OBSTACLES_MAX,
        "obstacles",
    );
    c.count(
        "ambient",
        layout.ambient.len(),
        AMBIENT_MAX,
        "ambient layers",
    );
    c.count("probes", layout.probes.len(), PROBES_MAX, "probes");
    let mut probe_ids = HashMap::new();
    for (k, probe) in layout.probes.iter().enumerate() {
        let p = format!("probes[{k}]");
        c.unique_id(&mut probe_ids, "probe", probe.id, &p);
        c.name(&format!("{p}.name"), &probe.name);
        c.point(&format!("{p}.pos"), probe.pos);
    }
    let nodes: usize = layout.trees.iter().map(|t| t.root.count()).sum();
    c.count(
        "trees",
        nodes,
        NODES_MAX,
        "points (roots and arrow ends) in all",
    );

    let mut tree_ids = HashMap::new();
    let mut node_ids = HashMap::new();
    for (t, tree) in layout.trees.iter().enumerate() {
        let p = format!("trees[{t}]");
        c.unique_id(&mut tree_ids, "tree", tree.id, &p);
        c.name(&format!("{p}.name"), &tree.name);
        c.bound(
            &format!("{p}.propagation_speed"),
            tree.propagation_speed,
            bounds::PROPAGATION_SPEED,
        );
        if let TimeWindow::Between { start, end } = tree.window {
            let ok = c.bound(&format!("{p}.window.start"), start, WINDOW_TIME);
            let ok = c.bound(&format!("{p}.window.end"), end, WINDOW_TIME) && ok;
            if ok && end <= start {
                c.push(
                    &format!("{p}.window.end"),
                    format!("must be after start ({start}), got {end}"),
                );
            }
        }
        if let Emission::Pulsed { period, duty } = tree.emission {
            c.bound(&format!("{p}.emission.period"), period, PERIOD);
            c.bound(&format!("{p}.emission.duty"), duty, DUTY);
        }
        check_keys(&mut c, &tree.keys, &format!("{p}.keys"));
        check_node(&mut c, &mut node_ids, &tree.root, &format!("{p}.root"), 0);
    }

    let mut obstacle_ids = HashMap::new();
    for (o, obstacle) in layout.obstacles.iter().enumerate() {
        let p = format!("obstacles[{o}]");
        c.unique_id(&mut obstacle_ids, "obstacle", obstacle.id, &p);
        c.name(&format!("{p}.name"), &obstacle.name);
        match &obstacle.shape {
            Shape::Circle { center, radius } => {
                c.point(&format!("{p}.shape.center"), *center);
                c.bound(&format!("{p}.shape.radius"), *radius, RADIUS);
            }
            Shape::Mask {
                image,
                threshold,
                rect,
                ..
            } => {
                if image.trim().is_empty() {
                    c.push(&format!("{p}.shape.image"), "must name an image file");
                }
                c.bound(&format!("{p}.shape.threshold"), *threshold, MASK_THRESHOLD);
                c.placement(&format!("{p}.shape.rect"), rect);
            }
            Shape::Polygon { points } => {
                c.count(
                    &format!("{p}.shape.points"),
                    points.len(),
                    POLYGON_POINTS_MAX,
                    "points",
                );
                if points.len() < 3 {
                    c.push(
                        &format!("{p}.shape.points"),
                        format!("a polygon needs at least 3 points, got {}", points.len()),
                    );
                }
                for (i, pt) in points.iter().enumerate() {
                    c.point(&format!("{p}.shape.points[{i}]"), *pt);
                }
                if points.len() >= 3 && points.iter().flatten().all(|v| v.is_finite()) {
                    let area = polygon_area(points);
                    if area.abs() < 1e-9 {
                        c.push(&format!("{p}.shape.points"), "polygon has zero area");
                    }
                }
            }
        }
    }

    let mut layer_ids = HashMap::new();
    for (a, layer) in layout.ambient.iter().enumerate() {
        let p = format!("ambient[{a}]");
        check_keys(&mut c, &layer.keys, &format!("{p}.keys"));
        c.unique_id(&mut layer_ids, "ambient layer", layer.id, &p);
        c.name(&format!("{p}.name"), &layer.name);
        let k = format!("{p}.kind");
        match &layer.kind {
            AmbientKind::Directional {
                direction_deg,
                main,
                turbulence,
                pulse_magnitude,
                pulse_frequency,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.bound(&format!("{k}.main"), *main, AMBIENT_SPEED);
                c.bound(&format!("{k}.turbulence"), *turbulence, AMBIENT_SPEED);
                c.bound(
                    &format!("{k}.pulse_magnitude"),
                    *pulse_magnitude,
                    PULSE_MAGNITUDE,
                );
                c.bound(
                    &format!("{k}.pulse_frequency"),
                    *pulse_frequency,
                    PULSE_FREQUENCY,
                );
            }
            AmbientKind::Noise {
                direction_deg,
                scale,
                speed,
                strength,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.bound(&format!("{k}.scale"), *scale, FEATURE_LENGTH);
                c.bound(&format!("{k}.speed"), *speed, SCROLL_SPEED);
                c.bound(&format!("{k}.strength"), *strength, AMBIENT_SPEED);
            }
            AmbientKind::Fft {
                direction_deg,
                wind_speed,
                amplitude,
                resolution,
                tile_size,
                seed: _,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.bound(&format!("{k}.wind_speed"), *wind_speed, FFT_WIND_SPEED);
                c.bound(&format!("{k}.amplitude"), *amplitude, AMBIENT_SPEED);
                if !resolution.is_power_of_two() || !FFT_RESOLUTION.contains(*resolution) {
                    c.push(
                        &format!("{k}.resolution"),
                        format!(
                            "must be a power of two from {} to {}, got {resolution}",
                            FFT_RESOLUTION.min, FFT_RESOLUTION.max
                        ),
                    );
                }
                c.bound(&format!("{k}.tile_size"), *tile_size, FEATURE_LENGTH);
            }
            AmbientKind::Sine {
                direction_deg,
                amplitude,
                wavelength,
                frequency,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.bound(&format!("{k}.amplitude"), *amplitude, AMBIENT_SPEED);
                c.bound(&format!("{k}.wavelength"), *wavelength, FEATURE_LENGTH);
                c.bound(&format!("{k}.frequency"), *frequency, SINE_FREQUENCY);
            }
        }
    }

    check_sim(&mut c, &layout.sim);
    check_grass(&mut c, &layout.grass);
    let [start, end] = layout.timeline.range;
    let ok = c.bound("timeline.range[0]", start, WINDOW_TIME);
    if c.bound("timeline.range[1]", end, WINDOW_TIME) && ok && end <= start {
        c.push(
            "timeline.range[1]",
            format!("must be after the play range's start ({start}), got {end}"),
        );
    }
    c.issues
}

fn check_world(c: &mut Checker, w: &World, pressure: PressureSolve) {
    c.bound("world.size[0]", w.size[0], WORLD_SIZE);
    c.bound("world.size[1]", w.size[1], WORLD_SIZE);
    c.point("world.origin", w.origin);
    let mut axes_ok = true;
    for (i, n) in w.grid.iter().enumerate() {
        if !(GRID_AXIS_MIN..=GRID_AXIS_MAX).contains(n) {
            axes_ok = false;
            c.push(
                &format!("world.grid[{i}]"),
                format!("must be between {GRID_AXIS_MIN} and {GRID_AXIS_MAX} cells, got {n}"),
            );
        }
    }
    let mut bytes = grid_memory(w.grid, pressure);
    if w.terrain.is_some() {
        bytes += u64::from(w.grid[0]) * u64::from(w.grid[1]) * TERRAIN_BYTES_PER_CELL;
    }
    if axes_ok && bytes > GRID_MEMORY_BUDGET {
        c.push(
            "world.grid",
            format!(
                "{}x{} needs {} of solver memory, over the budget of {}",
                w.grid[0],
                w.grid[1],
                mib(bytes),
                mib(GRID_MEMORY_BUDGET)
            ),
        );
    }
    if let Some(map) = &w.map {
        if map.image.trim().is_empty() {
            c.push("world.map.image", "must name an image file");
        }
        c.bound("world.map.opacity", map.opacity, OPACITY);
        c.placement("world.map.rect", &map.rect);
    }
    if let Some(t) = &w.terrain {
        if t.heightmap.trim().is_empty() {
            c.push("world.terrain.heightmap", "must name an image file");
        }
        c.min_max("world.terrain.heights", t.heights, TERRAIN_HEIGHT);
        c.placement("world.terrain.rect", &t.rect);
        c.bound("world.terrain.strength", t.strength, TERRAIN_STRENGTH);
        if let Some(l) = t.feature_length {
            c.bound("world.terrain.feature_length", l, FEATURE_LENGTH);
        }
    }
    let p = &w.profile;
    let z0 = c.bound(
        "world.profile.roughness_length",
        p.roughness_length,
        ROUGHNESS,
    );
    let href = c.bound(
        "world.profile.reference_height",
        p.reference_height,
        PROFILE_HEIGHT,
    );
    c.bound("world.profile.top", p.top, PROFILE_HEIGHT);
    c.whole("world.profile.layers", p.layers, PROFILE_LAYERS);
    if z0 && href && p.reference_height <= p.roughness_length {
        c.push(
            "world.profile.reference_height",
            format!(
                "must be above the roughness length ({} m), got {} m: the log law has no wind there",
                p.roughness_length, p.reference_height
            ),
        );
    }
}

/// `depth`: arrows from the tree's root to `n`.
fn check_node(c: &mut Checker, ids: &mut HashMap<u32, String>, n: &Node, path: &str, depth: usize) {
    c.unique_id(ids, "node", n.id, path);
    if depth == CHAIN_MAX && !n.children.is_empty() {
        c.push(
            &format!("{path}.children"),
            format!("a chain of arrows holds at most {CHAIN_MAX}; this one goes on past it"),
        );
        return;
    }
    let here = c.point(&format!("{path}.pos"), n.pos);
    c.bound(&format!("{path}.strength"), n.strength, STRENGTH);
    c.bound(&format!("{path}.radius"), n.radius, RADIUS);
    if !n.keys.is_empty() {
        if depth == 0 {
            c.push(
                &format!("{path}.keys"),
                "a root starts no arrow of its own: key the tree instead (its \"keys\")".to_owned(),
            );
        }
        check_keys(c, &n.keys, &format!("{path}.keys"));
    }
    for (i, child) in n.children.iter().enumerate() {
        let cp = format!("{path}.children[{i}]");
        let (dx, dz) = (child.pos[0] - n.pos[0], child.pos[1] - n.pos[1]);
        if here && dx.is_finite() && dz.is_finite() && crate::num::hypot(dx, dz) < LENGTH_MIN {
            c.push(
                &format!("{cp}.pos"),
                format!("an arrow end point must be at least {LENGTH_MIN} m from its start point"),
            );
        }
        check_node(c, ids, child, &cp, depth + 1);
    }
}

fn check_sim(c: &mut Checker, s: &SimParams) {
    c.bound("sim.dt", s.dt, DT);
    c.whole("sim.substeps", s.substeps, SUBSTEPS);
    c.whole("sim.pressure_cycles", s.pressure_cycles, PRESSURE_CYCLES);
    c.whole(
        "sim.pressure_iterations",
        s.pressure_iterations,
        PRESSURE_ITERATIONS,
    );
    c.bound("sim.pressure_decay", s.pressure_decay, PRESSURE_DECAY);
    c.bound("sim.vorticity", s.vorticity, VORTICITY);
    c.bound(
        "sim.velocity_dissipation",
        s.velocity_dissipation,
        VELOCITY_DISSIPATION,
    );
    c.bound("sim.ambient_coupling", s.ambient_coupling, AMBIENT_COUPLING);
    c.bound("sim.arrow_response", s.arrow_response, ARROW_RESPONSE);
}

fn check_grass(c: &mut Checker, g: &GrassParams) {
    c.bound("grass.density", g.density, GRASS_DENSITY);
    if let Some(m) = &g.density_map {
        if m.image.trim().is_empty() {
            c.push("grass.density_map.image", "must name an image file");
        }
        c.placement("grass.density_map.rect", &m.rect);
    }
    c.min_max("grass.height", g.height, BLADE_HEIGHT);
    c.min_max("grass.width", g.width, BLADE_WIDTH);
    c.min_max("grass.stiffness", g.stiffness, STIFFNESS);
    c.bound("grass.k1", g.k1, BEND);
    c.bound("grass.k2", g.k2, BEND);
    c.bound("grass.lambda", g.lambda, LAMBDA);
    let s = &g.shadow;
    let a = c.bound("grass.shadow.m_min", s.m_min, SHADOW_CLAMP);
    let b = c.bound("grass.shadow.m_max", s.m_max, SHADOW_CLAMP);
    if a && b && s.m_min > s.m_max {
        c.push(
            "grass.shadow.m_min",
            format!("must not exceed m_max ({}), got {}", s.m_max, s.m_min),
        );
    }
    c.bound("grass.shadow.c1", s.c1, SHADOW_TERM);
    c.bound("grass.shadow.c2", s.c2, SHADOW_TERM);
    if g.palettes.is_empty() {
        c.push("grass.palettes", "needs at least one palette");
    }
    for (i, p) in g.palettes.iter().enumerate() {
        for (j, v) in p.base.iter().enumerate() {
            c.bound(&format!("grass.palettes[{i}].base[{j}]"), *v, COLOUR);
        }
        for (j, v) in p.tip.iter().enumerate() {
            c.bound(&format!("grass.palettes[{i}].tip[{j}]"), *v, COLOUR);
        }
    }
}

/// Signed area of a polygon (shoelace).
pub fn polygon_area(points: &[Vec2]) -> f32 {
    let n = points.len();
    let mut a = 0.0;
    for i in 0..n {
        let p = points[i];
        let q = points[(i + 1) % n];
        a += p[0] * q[1] - q[0] * p[1];
    }
    a * 0.5
}

/// Ear-clipping triangulation of a simple polygon; calls `tri` with vertex indices.
pub fn for_each_ear(points: &[Vec2], mut tri: impl FnMut(usize, usize, usize)) {
    let n = points.len();
    if n < 3 {
        return;
    }
    let ccw = polygon_area(points) > 0.0;
    let mut idx: Vec<usize> = (0..n).collect();
    let cross =
        |a: Vec2, b: Vec2, c: Vec2| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut guard = 0;
    while idx.len() > 3 && guard < n * n {
        guard += 1;
        let m = idx.len();
        let mut clipped = false;
        for k in 0..m {
            let (ia, ib, ic) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
            let (a, b, c) = (points[ia], points[ib], points[ic]);
            let convex = if ccw {
                cross(a, b, c) > 0.0
            } else {
                cross(a, b, c) < 0.0
            };
            if !convex {
                continue;
            }
            let inside = idx.iter().any(|&q| {
                if q == ia || q == ib || q == ic {
                    return false;
                }
                let p = points[q];
                let (d1, d2, d3) = (cross(a, b, p), cross(b, c, p), cross(c, a, p));
                if ccw {
                    d1 > 0.0 && d2 > 0.0 && d3 > 0.0
                } else {
                    d1 < 0.0 && d2 < 0.0 && d3 < 0.0
                }
            });
            if inside {
                continue;
            }
            tri(ia, ib, ic);
            idx.remove(k);
            clipped = true;
            break;
        }
        if !clipped {
            break;
        }
    }
    if idx.len() == 3 {
        tri(idx[0], idx[1], idx[2]);
    }
}

/// What went wrong with the images the wind depends on, the mask obstacles' and the
/// terrain's heightmap: one line each, naming the field and the file (`io::load` reads them).
/// Empty when every one is loaded. A warning in the editor, `validate` and `render`; a refusal
/// in `bake`, which would ship wrong wind without them.
pub fn mask_problems(layout: &Layout) -> Vec<String> {
    let terrain = layout.world.terrain.as_ref().and_then(|t| match &t.pixels {
        MaskPixels::Loaded(_) => None,
        MaskPixels::Failed(why) => Some(format!("world.terrain: {why}")),
        MaskPixels::NotLoaded => Some(format!(
            "world.terrain: heightmap {} was not read",
            t.heightmap
        )),
    });
    terrain
        .into_iter()
        .chain(
            layout
                .obstacles
                .iter()
                .enumerate()
                .filter_map(|(k, o)| match &o.shape {
                    Shape::Mask { pixels, image, .. } => match pixels {
                        MaskPixels::Loaded(_) => None,
                        MaskPixels::Failed(why) => {
                            Some(format!("obstacles[{k}] \"{}\": {why}", o.name))
                        }
                        MaskPixels::NotLoaded => Some(format!(
                            "obstacles[{k}] \"{}\": mask image {image} was not read",
                            o.name
                        )),
                    },
                    _ => None,
                }),
        )
        .collect()
}

/// Why the grass's density map (if the layout has one) is not read: a warning — the grass
/// grows everywhere without it, and the wind does not depend on it.
pub fn density_map_problem(layout: &Layout) -> Option<String> {
    let map = layout.grass.density_map.as_ref()?;
    match &map.pixels {
        MaskPixels::Loaded(_) => None,
        MaskPixels::Failed(why) => Some(format!("grass.density_map: {why}")),
        MaskPixels::NotLoaded => Some(format!("grass.density_map: {} was not read", map.image)),
    }
}

/// A tree's or layer's keyframes: each value within its bound, at most [`KEYS_MAX`], the
/// times increasing.
fn check_keys(c: &mut Checker, keys: &[Key], path: &str) {
    c.count(path, keys.len(), KEYS_MAX, "keyframes");
    for (k, key) in keys.iter().enumerate() {
        let p = format!("{path}[{k}]");
        c.bound(&format!("{p}.time"), key.time, WINDOW_TIME);
        c.bound(&format!("{p}.strength"), key.strength, KEY_STRENGTH);
        c.bound(&format!("{p}.rotation_deg"), key.rotation_deg, KEY_ROTATION);
        if k > 0 && key.time.is_finite() && key.time <= keys[k - 1].time {
            c.push(
                &format!("{p}.time"),
                format!(
                    "keyframes go in time order: {} is not after the one before ({})",
                    key.time,
                    keys[k - 1].time
                ),
            );
        }
    }
}
