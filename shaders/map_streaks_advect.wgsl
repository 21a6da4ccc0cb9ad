// Map view, compute: streak particles advected through the wind where it lives, one
// invocation per particle. Each particle moves by the velocity at its head (bilinear between
// cell centres) times the frame's simulated seconds, keeps the last TRAIL points, and is
// reborn at a random world point when it dies (old age, leaving the world, or stuck in calm
// air). CPU twin: `app::view::Streaks::advance`.

@group(1) @binding(0) var<storage, read_write> stats: array<u32, 4>;
@group(1) @binding(1) var<storage, read_write> particles: array<Particle>;

fn spawn(k: u32, seed: u32, spread_age: bool) -> Particle {
    var q: Particle;
    let r = vec2<f32>(hash01(seed), hash01(seed ^ 0x9e3779b9u));
    q.trail[0] = mix(V.world_min, V.world_max, r);
    q.len = 1u;
    q.life = 1.5 + hash01(seed ^ 0x85ebca6bu) * 2.5;
    q.age = select(0.0, hash01(seed ^ 0xc2b2ae35u) * q.life, spread_age);
    q.seed = seed;
    return q;
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if (k >= V.particles) {
        return;
    }
    var q = particles[k];
    let fresh_seed = k * 2654435761u ^ (V.frame * 40503u + 1u);
    if (q.life <= 0.0) {
        // A new buffer is zeroed: start at random ages so births are spread out in time.
        particles[k] = spawn(k, fresh_seed, true);
        return;
    }
    if (V.dt <= 0.0) {
        return;
    }
    let head = q.trail[q.len - 1u];
    let vel = sample_velocity(head);
    let next = head + vel * V.dt;
    if (q.len < TRAIL) {
        q.trail[q.len] = next;
        q.len = q.len + 1u;
    } else {
        for (var n = 1u; n < TRAIL; n = n + 1u) {
            q.trail[n - 1u] = q.trail[n];
        }
        q.trail[TRAIL - 1u] = next;
    }
    q.age = q.age + V.dt;
    let out = any(next < V.world_min) || any(next > V.world_max);
    let calm = vel.x == 0.0 && vel.y == 0.0 && q.age > 0.5;
    if (q.age > q.life || out || calm) {
        q = spawn(k, fresh_seed, false);
    }
    particles[k] = q;
}
