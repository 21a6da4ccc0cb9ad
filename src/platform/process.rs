//! Other processes on this machine.

/// Whether process `pid` is still running on this machine, where the system tells: Linux
/// looks in /proc, other Unix asks kill(pid, 0) (a process of another user answers EPERM:
/// alive). `None` elsewhere: the caller decides what an unknown means.
pub fn alive(pid: u32) -> Option<bool> {
    #[cfg(target_os = "linux")]
    {
        Some(std::path::Path::new("/proc").join(pid.to_string()).exists())
    }
    #[cfg(all(unix, not(target_os = "linux")))]
    {
        let p = i32::try_from(pid)
            .ok()
            .and_then(rustix::process::Pid::from_raw)?;
        Some(match rustix::process::test_kill_process(p) {
            Ok(()) => true,
            Err(e) => e == rustix::io::Errno::PERM,
        })
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        None
    }
}

/// This machine's name and the id of its current boot, for a lock file a person reads
/// (Linux's /proc; empty where the system has no such file).
pub fn host_and_boot() -> (String, String) {
    let read = |p: &str| {
        std::fs::read_to_string(p)
            .unwrap_or_default()
            .trim()
            .to_string()
    };
    (
        read("/proc/sys/kernel/hostname"),
        read("/proc/sys/kernel/random/boot_id"),
    )
}

/// Shows `folder` in the system's file manager (Explorer, Finder, the desktop's default on
/// Linux), without waiting for it; why not, if it could not be started.
pub fn show_folder(folder: &std::path::Path) -> Result<(), String> {
    open::that_detached(folder).map_err(|e| format!("could not open {}: {e}", folder.display()))
}
