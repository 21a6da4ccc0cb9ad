//! The C interface (`windloom.h`, beside this file): the same calls for Unreal (C++), Unity
//! (C# P/Invoke), Godot (GDExtension) and any engine that can call C. A handle follows one
//! bake folder ([`LiveBake`]).
//!
//! Threads: queries (`windloom_wind_at`, `windloom_wind_at_many`, `windloom_info`) may run
//! on any number of threads at once; `windloom_reload` and `windloom_close` must not run
//! while another call uses the same handle. `windloom_last_error` is per thread.
//!
//! No panic crosses into the game: every entry point catches one and returns its failure
//! (NULL or -1) with `windloom_last_error` saying so. Time is a `double` of seconds.

use crate::{Axes, LiveBake, Options, Outside};
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};

/// An open bake folder (opaque to C).
pub struct WindloomWind {
    live: LiveBake,
}

/// What a bake holds, for a game to size its use of it (`windloom_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct WindloomInfo {
    /// The manifest's `sequence`: one more with every bake into the folder.
    pub sequence: u64,
    /// Cells along x and along z.
    pub grid: [u32; 2],
    /// The baked rectangle, windloom's axes (x east, z south), metres.
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub frames: u32,
    pub fps: f32,
    /// 1 when time wraps past the last frame.
    pub looped: u32,
    /// The seconds the frames span.
    pub duration: f32,
    /// The strongest baked wind, m/s.
    pub max_speed: f32,
    /// The bytes the bake takes in memory.
    pub memory_bytes: u64,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Keeps `message` as this thread's last error: one line, bounded (control characters
/// escaped, at most [`crate::MAX_ERROR_CHARS`] characters).
fn set_error(message: &str) {
    let line = crate::file::one_line(message);
    let c = CString::new(line.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Runs `f`, turning a panic (a bug) into `failed` with a last error naming `call`.
fn guarded<T>(call: &str, failed: T, f: impl FnOnce() -> T) -> T {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|_| {
        set_error(&format!(
            "{call}: the runtime failed (a bug: please report it with the bake)"
        ));
        failed
    })
}

fn axes(n: u32) -> Option<Axes> {
    Some(match n {
        0 => Axes::Windloom,
        1 => Axes::Unity,
        2 => Axes::Unreal,
        _ => return None,
    })
}

fn outside(n: u32) -> Option<Outside> {
    Some(match n {
        0 => Outside::Clamp,
        1 => Outside::Zero,
        2 => Outside::Wrap,
        _ => return None,
    })
}

/// Opens the bake in `folder` (a UTF-8 path), answering in `axes` (0 windloom/Godot/Bevy,
/// 1 Unity, 2 Unreal) with `outside` beyond the rectangle (0 clamp, 1 zero, 2 wrap).
/// NULL on failure, with `windloom_last_error` saying why.
///
/// # Safety
/// `folder` is NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_open(
    folder: *const c_char,
    axes_code: u32,
    outside_code: u32,
) -> *mut WindloomWind {
    if folder.is_null() {
        set_error("windloom_open: the folder is NULL");
        return std::ptr::null_mut();
    }
    // SAFETY: the caller passes a NUL-terminated string (this function's contract).
    let folder = unsafe { CStr::from_ptr(folder) };
    let Ok(folder) = folder.to_str() else {
        set_error("windloom_open: the folder is not UTF-8");
        return std::ptr::null_mut();
    };
    let (Some(a), Some(o)) = (axes(axes_code), outside(outside_code)) else {
        set_error(&format!(
            "windloom_open: axes {axes_code} or outside {outside_code} is not one of windloom.h's"
        ));
        return std::ptr::null_mut();
    };
    let options = Options {
        axes: a,
        outside: o,
        format: None,
    };
    guarded(
        "windloom_open",
        std::ptr::null_mut(),
        || match LiveBake::open(folder, options) {
            Ok(live) => {
                set_error("");
                Box::into_raw(Box::new(WindloomWind { live }))
            }
            Err(e) => {
                set_error(&e.to_string());
                std::ptr::null_mut()
            }
        },
    )
}

/// Why this thread's last call failed, or "" (valid until this thread's next call).
#[unsafe(no_mangle)]
pub extern "C" fn windloom_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// The wind at `(x, y, z)` at `t` seconds into `out[0..3]`, in the handle's axes (m/s; cm/s
/// in Unreal's). 0 on success, -1 for a NULL pointer.
///
/// `t` is the game's clock in seconds, as a `double`: it need not be wrapped, a clock a
/// month on reads the wind as precisely as one just started.
///
/// # Safety
/// `wind` is NULL or a handle from `windloom_open` not yet closed; `out` is NULL or points
/// to 3 writable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_wind_at(
    wind: *const WindloomWind,
    x: f32,
    y: f32,
    z: f32,
    t: f64,
    out: *mut f32,
) -> i32 {
    if wind.is_null() || out.is_null() {
        set_error("windloom_wind_at: the handle or `out` is NULL");
        return -1;
    }
    // SAFETY: a live handle from windloom_open (the contract); only read here.
    let w = unsafe { &*wind };
    let Some(v) = guarded("windloom_wind_at", None, || {
        Some(w.live.bake().wind_at([x, y, z], t))
    }) else {
        return -1;
    };
    // SAFETY: `out` points to 3 writable floats (the contract).
    unsafe { std::ptr::copy_nonoverlapping(v.as_ptr(), out, 3) };
    0
}

/// The wind at `count` positions (`positions[3k..3k+3]`) at `t` seconds into `out` (3 floats
/// a position). 0 on success, -1 for a NULL pointer.
///
/// # Safety
/// `wind` is a live handle; `positions` and `out` each point to `3 × count` floats (`out`
/// writable); they may not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_wind_at_many(
    wind: *const WindloomWind,
    positions: *const f32,
    count: usize,
    t: f64,
    out: *mut f32,
) -> i32 {
    if count == 0 {
        return 0;
    }
    if wind.is_null() || positions.is_null() || out.is_null() {
        set_error("windloom_wind_at_many: the handle, `positions` or `out` is NULL");
        return -1;
    }
    // No slice may span more than isize::MAX bytes: a larger count cannot be an array.
    if count > isize::MAX as usize / std::mem::size_of::<[f32; 3]>() {
        set_error(&format!(
            "windloom_wind_at_many: count {count} is more positions than memory holds"
        ));
        return -1;
    }
    // SAFETY: a live handle (the contract).
    let w = unsafe { &*wind };
    // SAFETY: `positions` holds 3 × count floats, and [f32; 3] has their layout and alignment.
    let p = unsafe { std::slice::from_raw_parts(positions.cast::<[f32; 3]>(), count) };
    // SAFETY: `out` holds 3 × count writable floats, apart from `positions`.
    let o = unsafe { std::slice::from_raw_parts_mut(out.cast::<[f32; 3]>(), count) };
    guarded("windloom_wind_at_many", -1, || {
        w.live.bake().wind_at_many(p, t, o);
        0
    })
}

/// Looks for a new bake in the folder (cheap when there is none: one small file read).
/// 1 when a new bake now answers, 0 when nothing changed, -1 when the new bake could not be
/// read (`windloom_last_error` says why; the last good bake goes on answering).
///
/// # Safety
/// `wind` is NULL or a live handle, used by no other thread during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_reload(wind: *mut WindloomWind) -> i32 {
    if wind.is_null() {
        set_error("windloom_reload: the handle is NULL");
        return -1;
    }
    // SAFETY: a live handle, used by no other thread now (the contract).
    let w = unsafe { &mut *wind };
    guarded("windloom_reload", -1, || match w.live.poll() {
        Ok(changed) => {
            // The last good read is the newest: an old failure is no longer the news.
            if w.live.last_error().is_none() {
                set_error("");
            }
            i32::from(changed)
        }
        Err(e) => {
            set_error(&e.to_string());
            -1
        }
    })
}

/// What the answering bake holds, into `out`. 0 on success, -1 for a NULL pointer.
///
/// # Safety
/// `wind` is NULL or a live handle; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_info(wind: *const WindloomWind, out: *mut WindloomInfo) -> i32 {
    if wind.is_null() || out.is_null() {
        set_error("windloom_info: the handle or `out` is NULL");
        return -1;
    }
    // SAFETY: a live handle (the contract).
    let b = unsafe { &*wind }.live.bake();
    let (min, max) = b.bounds();
    let g = b.grid();
    let info = WindloomInfo {
        sequence: b.sequence(),
        grid: [g[0] as u32, g[1] as u32],
        min,
        max,
        frames: b.frames() as u32,
        fps: b.fps(),
        looped: u32::from(b.looped()),
        duration: b.duration(),
        max_speed: b.max_speed(),
        memory_bytes: b.memory_bytes() as u64,
    };
    // SAFETY: `out` is writable (the contract).
    unsafe { out.write(info) };
    0
}

/// Closes a handle (NULL is ignored).
///
/// # Safety
/// `wind` is NULL or a live handle no other call is using; it is not used again.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn windloom_close(wind: *mut WindloomWind) {
    if !wind.is_null() {
        // SAFETY: from Box::into_raw in windloom_open, closed once (the contract).
        drop(unsafe { Box::from_raw(wind) });
    }
}
