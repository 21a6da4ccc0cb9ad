//! What differs between Windows, macOS and Linux, one small module per concern, so the rest
//! of the crate has no `cfg`: the file system ([`fs`]) and other processes ([`process`]).
//! Each function says what it does where the system has no such thing.

pub mod fs;
pub mod process;
