//! The simulation: the CPU solver behaves like a fluid and the force model like the paper's
//! AGC trees, the fast passes give the reference's bits, every layout stays bounded, and the
//! GPU passes and the grass match their CPU twins. One test binary, a module per concern;
//! the helpers here are shared by them.
#![allow(
    clippy::unwrap_used,
    reason = "a test that unwraps fails there, which is what a test is for"
)]

use proptest::prelude::*;
use std::path::Path;
use windloom::doc::{self, Boundary, Emission, Layout, Node, Shape, TimeWindow, Tree};
use windloom::sim::{Solver, forces};

fn example(name: &str) -> Layout {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name);
    windloom::io::load(&p).unwrap_or_else(|e| panic!("{e}"))
}

/// Every bundled example layout.
const EXAMPLES: [&str; 6] = [
    "meadow.json",
    "obstacles.json",
    "two-winds.json",
    "breeze-fft.json",
    "branching.json",
    "walled-garden.json",
];

/// Example `name` at its own grid, or resized to `grid`, run from rest on the CPU until its
/// flow is developed (30 steps; 8 on a resized grid, which is the big one): the layout and
/// the solver.
fn developed(name: &str, grid: Option<[u32; 2]>) -> (Layout, Solver) {
    let mut l = example(name);
    if let Some(g) = grid {
        l.world.grid = g;
    }
    let mut s = Solver::new(&l);
    for _ in 0..if grid.is_some() { 8 } else { 30 } {
        s.step();
    }
    (l, s)
}

fn tree(id: u32, root: Node) -> Tree {
    Tree {
        id,
        name: format!("tree {id}"),
        enabled: true,
        window: TimeWindow::Always,
        emission: Emission::Continuous,
        propagation_speed: 50.0,
        root,
        locked: false,
        hidden: false,
        keys: Vec::new(),
    }
}

/// A chain root → a → b … through `points`, every arrow with the same strength and radius.
fn chain(first_id: u32, points: &[[f32; 2]], strength: f32, radius: f32) -> Node {
    let mut node: Option<Node> = None;
    for (k, p) in points.iter().enumerate().rev() {
        let mut n = Node::new(first_id + k as u32, *p, strength, radius);
        if let Some(child) = node.take() {
            n.children.push(child);
        }
        node = Some(n);
    }
    node.unwrap()
}

fn run(solver: &mut Solver, seconds: f32) {
    let steps = (seconds / solver.params.dt).round() as usize;
    for _ in 0..steps {
        solver.step();
    }
}

/// Deterministic pseudo-random values in [-1, 1].
fn noise_field(n: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        })
        .collect()
}

/// A solver for `l` whose faces hold white noise of amplitude `a` (u from `seeds.0`, v from
/// `seeds.1`), with the boundaries enforced.
fn noisy_solver(l: &Layout, seeds: (u64, u64), a: f32) -> Solver {
    let mut s = Solver::new(l);
    let (u, v) = s.faces_mut();
    for (f, seed) in [(u, seeds.0), (v, seeds.1)] {
        let noise = noise_field(f.len(), seed);
        for (x, n) in f.iter_mut().zip(noise) {
            *x = a * n;
        }
    }
    s.enforce_boundaries();
    s
}

fn random_solver(boundary: Boundary, n: u32) -> Solver {
    let mut l = Layout::new("random", [64.0, 64.0], [n, n]);
    l.sim.boundary = boundary;
    l.sim.pressure_decay = 0.0;
    noisy_solver(&l, (1, 2), 1.0)
}

/// One `#[test]` per bundled example, named after it, each calling `$check("file.json")`:
/// how a check that runs every example for long is split, so that the two cores run the
/// examples side by side (docs/CODE_STYLE.md, "What a test may cost").
macro_rules! test_each_example {
    ($check:path) => {
        test_each_example!(@ $check: meadow "meadow.json", obstacles "obstacles.json",
            two_winds "two-winds.json", breeze_fft "breeze-fft.json",
            branching "branching.json", walled_garden "walled-garden.json");
    };
    (@ $check:path: $($test:ident $file:literal),*) => {
        // The list above and `EXAMPLES` name the same files.
        const _: () = assert!([$($file),*].len() == $crate::EXAMPLES.len());
        $(
            #[test]
            fn $test() {
                assert!($crate::EXAMPLES.contains(&$file), "{} is not an example", $file);
                $check($file);
            }
        )*
    };
}

mod bench;
mod bits;
mod fluid;
mod forcing;
/// Obstacles from a level's collision mask.
mod keys;
mod masks;
mod presets;
mod pressure;
mod stability;
mod terrain;

// ---- The GPU passes against the CPU ---------------------------------------------------------

mod gpu;

/// The grass model's CPU side: placement and the CWD deformation (the GPU's twin).
mod grass;
