//! Semantic validation of a [`Layout`]: every problem, each with the JSON path of its field.

use super::types::*;
use std::collections::HashMap;
use std::fmt;

/// The solver's working memory per grid cell in bytes (velocity faces, temporaries, pressure,
/// divergence, curl, solid mask). The CPU solver checks its own allocation against this.
pub const SOLVER_BYTES_PER_CELL: u64 = 56;
/// What the multigrid hierarchy adds per grid cell (`sim.pressure = "multigrid"`): the fine
/// level's links and diagonal (16) and the coarser levels' links and unknowns (at most 28 over
/// all of them, when every level halves one axis only).
pub const MULTIGRID_BYTES_PER_CELL: u64 = 44;
/// Largest solver memory a layout may ask for: 2 GiB.
pub const GRID_MEMORY_BUDGET: u64 = 2 << 30;
/// Grid axes must lie in this range.
pub const GRID_AXIS_MIN: u32 = 8;
pub const GRID_AXIS_MAX: u32 = 16384;
/// Largest world side in metres.
pub const WORLD_SIZE_MAX: f32 = 100_000.0;
/// Smallest world side in metres: with at most [`GRID_AXIS_MAX`] cells a side, cells stay
/// above 0.06 mm, so the solver's `1/h²` and the renderer's scale stay finite.
pub const WORLD_SIZE_MIN: f32 = 1.0;
/// Largest distance (metres) of any position (origin, node, obstacle point) from the world
/// origin `[0, 0]`. Far beyond any level, and small enough that every position, scaled to
/// pixels or cells, stays a finite and precise `f32`.
pub const COORD_MAX: f32 = 1.0e6;
/// Smallest radius, noise scale, wavelength, tile or arrow length in metres: below it the
/// Gaussian `1/r²` and friends overflow `f32`.
pub const LENGTH_MIN: f32 = 1.0e-3;
/// Smallest and largest solver step in seconds. The largest keeps the solver stable; the
/// smallest keeps a bake's step count (seconds / dt) finite.
pub const DT_MIN: f32 = 1.0e-4;
pub const DT_MAX: f32 = 1.0 / 30.0;
/// Largest arrow strength (target wind speed, m/s) and radius (m) accepted.
pub const STRENGTH_MAX: f32 = 500.0;
pub const RADIUS_MAX: f32 = 100_000.0;

/// Largest layout file windloom reads, in bytes. A layout at every count limit below stays
/// well under it; a file past it is refused before it is parsed (a 58 MB layout took 1.8 GB
/// and 10 s to read).
pub const LAYOUT_MAX_BYTES: u64 = 16 << 20;
/// Longest chain of arrows in a tree: arrows from its root to its farthest end point.
pub const CHAIN_MAX: usize = 160;
/// Most points (roots and arrow end points) in a layout, over all its trees.
pub const NODES_MAX: usize = 10_000;
/// Most wind trees, obstacles and ambient layers in a layout.
pub const TREES_MAX: usize = 1_000;
pub const OBSTACLES_MAX: usize = 10_000;
pub const AMBIENT_MAX: usize = 64;
/// Most points of one polygon obstacle.
pub const POLYGON_POINTS_MAX: usize = 10_000;
/// Longest name (of the layout, a tree, an obstacle or a layer), in characters.
pub const NAME_MAX: usize = 256;
/// How deep a layout's JSON may nest, counting each open object, array and field (a chain of
/// [`CHAIN_MAX`] arrows takes three levels an arrow, 490 in all): within the 512 that the
/// parser that locates fields and finds duplicate keys reads.
pub const NESTING_MAX: usize = 500;
const _: () = assert!(3 * CHAIN_MAX + 10 <= NESTING_MAX && NESTING_MAX <= 512);

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

    /// Finite and strictly positive, at most `hi`.
    fn positive(&mut self, path: &str, v: f32, hi: f32) -> bool {
        self.positive_from(path, v, 0.0, hi)
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

    fn finite(&mut self, path: &str, v: f32) -> bool {
        self.range(path, v, f32::MIN, f32::MAX)
    }

    /// A position: each coordinate within ±[`COORD_MAX`].
    fn point(&mut self, path: &str, p: Vec2) -> bool {
        let a = self.range(&format!("{path}[0]"), p[0], -COORD_MAX, COORD_MAX);
        let b = self.range(&format!("{path}[1]"), p[1], -COORD_MAX, COORD_MAX);
        a && b
    }

    fn min_max(&mut self, path: &str, r: Vec2, hi: f32) {
        let a = self.positive(&format!("{path}[0]"), r[0], hi);
        let b = self.positive(&format!("{path}[1]"), r[1], hi);
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
        c.positive_from(
            &format!("{p}.propagation_speed"),
            tree.propagation_speed,
            LENGTH_MIN,
            1.0e6,
        );
        if let TimeWindow::Between { start, end } = tree.window {
            let ok = c.range(&format!("{p}.window.start"), start, 0.0, 1.0e7);
            let ok = c.range(&format!("{p}.window.end"), end, 0.0, 1.0e7) && ok;
            if ok && end <= start {
                c.push(
                    &format!("{p}.window.end"),
                    format!("must be after start ({start}), got {end}"),
                );
            }
        }
        if let Emission::Pulsed { period, duty } = tree.emission {
            c.positive_from(&format!("{p}.emission.period"), period, LENGTH_MIN, 1.0e6);
            c.positive(&format!("{p}.emission.duty"), duty, 1.0);
        }
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
                c.positive_from(
                    &format!("{p}.shape.radius"),
                    *radius,
                    LENGTH_MIN,
                    RADIUS_MAX,
                );
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
                c.range(&format!("{k}.main"), *main, 0.0, 500.0);
                c.range(&format!("{k}.turbulence"), *turbulence, 0.0, 500.0);
                c.range(&format!("{k}.pulse_magnitude"), *pulse_magnitude, 0.0, 10.0);
                c.range(
                    &format!("{k}.pulse_frequency"),
                    *pulse_frequency,
                    0.0,
                    100.0,
                );
            }
            AmbientKind::Noise {
                direction_deg,
                scale,
                speed,
                strength,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.positive_from(&format!("{k}.scale"), *scale, LENGTH_MIN, WORLD_SIZE_MAX);
                c.range(&format!("{k}.speed"), *speed, 0.0, 1000.0);
                c.range(&format!("{k}.strength"), *strength, 0.0, 500.0);
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
                c.positive_from(&format!("{k}.wind_speed"), *wind_speed, 0.01, 500.0);
                c.range(&format!("{k}.amplitude"), *amplitude, 0.0, 500.0);
                if !resolution.is_power_of_two() || !(8..=512).contains(resolution) {
                    c.push(
                        &format!("{k}.resolution"),
                        format!("must be a power of two from 8 to 512, got {resolution}"),
                    );
                }
                c.positive_from(
                    &format!("{k}.tile_size"),
                    *tile_size,
                    LENGTH_MIN,
                    WORLD_SIZE_MAX,
                );
            }
            AmbientKind::Sine {
                direction_deg,
                amplitude,
                wavelength,
                frequency,
            } => {
                c.finite(&format!("{k}.direction_deg"), *direction_deg);
                c.range(&format!("{k}.amplitude"), *amplitude, 0.0, 500.0);
                c.positive_from(
                    &format!("{k}.wavelength"),
                    *wavelength,
                    LENGTH_MIN,
                    WORLD_SIZE_MAX,
                );
                c.range(&format!("{k}.frequency"), *frequency, -100.0, 100.0);
            }
        }
    }

    check_sim(&mut c, &layout.sim);
    check_grass(&mut c, &layout.grass);
    c.issues
}

fn check_world(c: &mut Checker, w: &World, pressure: PressureSolve) {
    c.positive_from("world.size[0]", w.size[0], WORLD_SIZE_MIN, WORLD_SIZE_MAX);
    c.positive_from("world.size[1]", w.size[1], WORLD_SIZE_MIN, WORLD_SIZE_MAX);
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
    let bytes = grid_memory(w.grid, pressure);
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
        c.range("world.map.opacity", map.opacity, 0.0, 1.0);
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
    c.range(&format!("{path}.strength"), n.strength, 0.0, STRENGTH_MAX);
    c.positive_from(&format!("{path}.radius"), n.radius, LENGTH_MIN, RADIUS_MAX);
    for (i, child) in n.children.iter().enumerate() {
        let cp = format!("{path}.children[{i}]");
        let (dx, dz) = (child.pos[0] - n.pos[0], child.pos[1] - n.pos[1]);
        if here && dx.is_finite() && dz.is_finite() && dx.hypot(dz) < LENGTH_MIN {
            c.push(
                &format!("{cp}.pos"),
                format!("an arrow end point must be at least {LENGTH_MIN} m from its start point"),
            );
        }
        check_node(c, ids, child, &cp, depth + 1);
    }
}

fn check_sim(c: &mut Checker, s: &SimParams) {
    c.positive_from("sim.dt", s.dt, DT_MIN, DT_MAX);
    if !(1..=16).contains(&s.substeps) {
        c.push(
            "sim.substeps",
            format!("must be between 1 and 16, got {}", s.substeps),
        );
    }
    if !(1..=20).contains(&s.pressure_cycles) {
        c.push(
            "sim.pressure_cycles",
            format!("must be between 1 and 20, got {}", s.pressure_cycles),
        );
    }
    if !(1..=1000).contains(&s.pressure_iterations) {
        c.push(
            "sim.pressure_iterations",
            format!("must be between 1 and 1000, got {}", s.pressure_iterations),
        );
    }
    c.range("sim.pressure_decay", s.pressure_decay, 0.0, 1.0);
    c.range("sim.vorticity", s.vorticity, 0.0, 1000.0);
    c.range(
        "sim.velocity_dissipation",
        s.velocity_dissipation,
        0.0,
        100.0,
    );
    c.range("sim.ambient_coupling", s.ambient_coupling, 0.0, 100.0);
    c.range("sim.arrow_response", s.arrow_response, 0.0, 1000.0);
}

fn check_grass(c: &mut Checker, g: &GrassParams) {
    c.positive("grass.density", g.density, 100_000.0);
    c.min_max("grass.height", g.height, 100.0);
    c.min_max("grass.width", g.width, 10.0);
    c.min_max("grass.stiffness", g.stiffness, 1000.0);
    c.range("grass.k1", g.k1, 0.0, 10.0);
    c.range("grass.k2", g.k2, 0.0, 10.0);
    c.range("grass.lambda", g.lambda, 0.0, 1.0);
    let s = &g.shadow;
    let a = c.range("grass.shadow.m_min", s.m_min, 0.0, 10.0);
    let b = c.range("grass.shadow.m_max", s.m_max, 0.0, 10.0);
    if a && b && s.m_min > s.m_max {
        c.push(
            "grass.shadow.m_min",
            format!("must not exceed m_max ({}), got {}", s.m_max, s.m_min),
        );
    }
    c.range("grass.shadow.c1", s.c1, -100.0, 100.0);
    c.range("grass.shadow.c2", s.c2, -100.0, 100.0);
    if g.palettes.is_empty() {
        c.push("grass.palettes", "needs at least one palette");
    }
    for (i, p) in g.palettes.iter().enumerate() {
        for (j, v) in p.base.iter().enumerate() {
            c.range(&format!("grass.palettes[{i}].base[{j}]"), *v, 0.0, 1.0);
        }
        for (j, v) in p.tip.iter().enumerate() {
            c.range(&format!("grass.palettes[{i}].tip[{j}]"), *v, 0.0, 1.0);
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
