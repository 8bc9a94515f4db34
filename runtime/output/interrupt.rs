//! SIGINT/SIGTERM during `run` (issue 15 class 3): the temp files of the run are removed, one
//! line says what happened, and the process exits with 130 (SIGINT) or 143 (SIGTERM).
//!
//! The handler does only what POSIX allows in a signal handler (`unlink`, `write`, `_exit`) on
//! paths prepared beforehand, so it is safe whatever the run was doing.

use std::ffi::CString;
use std::path::Path;
use std::sync::OnceLock;

static TEMP_FILES: OnceLock<Vec<CString>> = OnceLock::new();

/// Installs the handler; on a signal, `paths` (the `*.tmp` files of this run) are removed.
/// Call once per process (later calls keep the first list).
pub fn clean_up_on_signal(paths: &[&Path]) {
    use std::os::unix::ffi::OsStrExt;
    let list = paths
        .iter()
        .filter_map(|p| CString::new(p.as_os_str().as_bytes()).ok())
        .collect();
    if TEMP_FILES.set(list).is_err() {
        return;
    }
    let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: `on_signal` only calls async-signal-safe functions on data fixed before this call.
    unsafe {
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

extern "C" fn on_signal(sig: libc::c_int) {
    let msg: &[u8] = if sig == libc::SIGINT {
        b"\ninterrupted (SIGINT): run stopped, temporary files removed, no results written\n"
    } else {
        b"\nterminated (SIGTERM): run stopped, temporary files removed, no results written\n"
    };
    // SAFETY: unlink, write and _exit are async-signal-safe; the strings live for the process.
    unsafe {
        if let Some(list) = TEMP_FILES.get() {
            for p in list {
                libc::unlink(p.as_ptr());
            }
        }
        libc::write(2, msg.as_ptr().cast(), msg.len());
        libc::_exit(128 + sig);
    }
}
