//! The transcendental functions whose results reach a bake, a render or a layout, computed
//! the same way, to the bit, on every platform. The standard library's `f32::sin` and kin
//! call the platform's C maths library (glibc, mingw's msvcrt, Apple's libm), whose last
//! bits differ: a bake made on Windows differed from the Linux bake of the same layout by up
//! to 2.9e-6 m/s. These call the `libm` crate (a port of musl's, in Rust) instead, so a bake
//! is byte-identical wherever it is made. `sqrt` needs no twin: IEEE 754 rounds it exactly.

/// `x.sin()`.
pub fn sin(x: f32) -> f32 {
    libm::sinf(x)
}

/// `x.cos()`.
pub fn cos(x: f32) -> f32 {
    libm::cosf(x)
}

/// `x.sin_cos()`.
pub fn sin_cos(x: f32) -> (f32, f32) {
    libm::sincosf(x)
}

/// `x.exp()`.
pub fn exp(x: f32) -> f32 {
    libm::expf(x)
}

/// `x.ln()`.
pub fn ln(x: f32) -> f32 {
    libm::logf(x)
}

/// `x.log10()`.
pub fn log10(x: f32) -> f32 {
    libm::log10f(x)
}

/// `x.powf(y)`.
pub fn powf(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// `x.tanh()`.
pub fn tanh(x: f32) -> f32 {
    libm::tanhf(x)
}

/// `y.atan2(x)`.
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// `x.hypot(y)`.
pub fn hypot(x: f32, y: f32) -> f32 {
    libm::hypotf(x, y)
}

/// `x.ln()` in double precision.
pub fn ln64(x: f64) -> f64 {
    libm::log(x)
}

/// `x.cos()` in double precision.
pub fn cos64(x: f64) -> f64 {
    libm::cos(x)
}

#[cfg(test)]
mod tests {
    /// The twins agree with the platform's functions to within a few units in the last
    /// place: they change which bits, not what the wind is.
    #[test]
    fn the_twins_agree_with_the_platform_within_rounding() {
        let close =
            |a: f32, b: f32| (a - b).abs() <= 4.0 * f32::EPSILON * a.abs().max(b.abs()).max(1e-30);
        for i in -2000..2000 {
            let x = i as f32 * 0.0137;
            assert!(close(super::sin(x), x.sin()), "sin {x}");
            assert!(close(super::cos(x), x.cos()), "cos {x}");
            assert!(close(super::exp(x * 0.05), (x * 0.05).exp()), "exp {x}");
            assert!(close(super::tanh(x), x.tanh()), "tanh {x}");
            assert!(close(super::atan2(x, 1.3), x.atan2(1.3)), "atan2 {x}");
            assert!(close(super::hypot(x, 2.0), x.hypot(2.0)), "hypot {x}");
            let (s, c) = super::sin_cos(x);
            assert!(close(s, x.sin()) && close(c, x.cos()), "sin_cos {x}");
            if x > 0.0 {
                assert!(close(super::ln(x), x.ln()), "ln {x}");
                assert!(close(super::log10(x), x.log10()), "log10 {x}");
                assert!(close(super::powf(x, 1.7), x.powf(1.7)), "powf {x}");
            }
            let d = f64::from(x);
            assert!(
                (super::cos64(d) - d.cos()).abs() <= 4.0 * f64::EPSILON,
                "cos64 {x}"
            );
        }
    }
}
