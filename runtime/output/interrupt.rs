//! SIGINT/SIGTERM during `run` (issue 15 class 3): the temp files of the run are removed, one
//! line says what happened, and the process exits with 130 (SIGINT) or 143 (SIGTERM).
//! During a sweep ([`cancel_on_signal`]) the first signal only sets a flag, so the sweep can keep
//! its whole rows and exit on its own.
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
    // `on_signal` only calls async-signal-safe functions on data fixed before this call.
    install(on_signal);
}

/// `handler` for SIGINT and SIGTERM. The caller guarantees that it calls only
/// async-signal-safe functions on data fixed before the call.
fn install(handler: extern "C" fn(libc::c_int)) {
    let handler = handler as libc::sighandler_t;
    // SAFETY: installing a handler is safe; what it may do is the caller's guarantee above.
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

static EXIT_NOTE: OnceLock<CString> = OnceLock::new();

/// For work that keeps its finished parts (`figure`): on SIGINT/SIGTERM print `note` on its
/// own line and exit with 128 + signal (the parts are written atomically, so what is on disk
/// is whole). Call once per process.
pub fn note_on_signal(note: &str) {
    let Ok(text) = CString::new(format!("\ninterrupted: {note}\n")) else { return };
    if EXIT_NOTE.set(text).is_err() {
        return;
    }
    // `on_note_signal` only calls write and _exit on a string fixed before this call.
    install(on_note_signal);
}

extern "C" fn on_note_signal(sig: libc::c_int) {
    // SAFETY: write and _exit are async-signal-safe; the string lives for the process.
    unsafe {
        if let Some(t) = EXIT_NOTE.get() {
            let b = t.as_bytes();
            libc::write(2, b.as_ptr().cast(), b.len());
        }
        libc::_exit(128 + sig);
    }
}

static CANCEL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
static SIGNAL: std::sync::atomic::AtomicI32 = std::sync::atomic::AtomicI32::new(0);

/// The signal that set the [`cancel_on_signal`] flag, if one did.
pub fn cancelling_signal() -> Option<i32> {
    Some(SIGNAL.load(std::sync::atomic::Ordering::SeqCst)).filter(|&s| s != 0)
}

/// For sweeps: the first SIGINT/SIGTERM only sets the returned flag (the sweep stops starting
/// runs, abandons those in flight and keeps its whole rows); a second one exits at once with
/// 128 + signal (rows already written stay whole: each is one `write`). Replaces
/// [`clean_up_on_signal`]'s handler; call once per process.
pub fn cancel_on_signal() -> &'static std::sync::atomic::AtomicBool {
    let handler = on_cancel_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: `on_cancel_signal` only touches an atomic and calls write/_exit.
    unsafe {
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
    &CANCEL
}

extern "C" fn on_cancel_signal(sig: libc::c_int) {
    let _ = SIGNAL.compare_exchange(0, sig, std::sync::atomic::Ordering::SeqCst, std::sync::atomic::Ordering::SeqCst);
    let first = !CANCEL.swap(true, std::sync::atomic::Ordering::SeqCst);
    let msg: &[u8] = if first {
        b"\ninterrupted: stopping (runs in progress are abandoned; finished rows are kept; press again to quit at once)\n"
    } else {
        b"\ninterrupted again: quitting now (finished rows are kept; rerun to resume)\n"
    };
    // SAFETY: write and _exit are async-signal-safe; the strings are static.
    unsafe {
        libc::write(2, msg.as_ptr().cast(), msg.len());
        if !first {
            libc::_exit(128 + sig);
        }
    }
}
