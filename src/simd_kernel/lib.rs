//! `#[simd_kernel]`: compiles a function for every SIMD level the `multiversion` crate
//! targets, the widest the CPU has picked when it is first called; with
//! `--cfg windloom_static_simd` (and a `-C target-cpu=…`) picked when it is compiled instead,
//! which is how an AVX2 build is measured on an AVX-512 host (`docs/PERFORMANCE.md`).
//!
//! It writes the two `cfg_attr`s every kernel of windloom's solver carried, once. The crate
//! using it depends on `multiversion`.

use proc_macro::TokenStream;

/// The `multiversion` attributes that come before the function.
const ATTRIBUTES: &str = r#"
    #[cfg_attr(not(windloom_static_simd), ::multiversion::multiversion(targets = "simd"))]
    #[cfg_attr(
        windloom_static_simd,
        ::multiversion::multiversion(targets = "simd", dispatcher = "static")
    )]
"#;

/// Compiles the function for every SIMD level; takes no arguments.
#[proc_macro_attribute]
pub fn simd_kernel(args: TokenStream, item: TokenStream) -> TokenStream {
    if !args.is_empty() {
        return r##"compile_error!("#[simd_kernel] takes no arguments");"##
            .parse()
            .expect("a valid compile_error! call");
    }
    let mut out: TokenStream = ATTRIBUTES.parse().expect("valid attributes");
    out.extend(item);
    out
}
