//! One process at a time in an output directory (issue 29 item 3): an advisory lock on the
//! directory itself (`flock` through the `fs4` crate), taken before anything is written into it
//! and held until the command is done. A second process that wants the same directory gets
//! [`OutputError::Busy`] naming the owner's pid (from `.magbubble.lock`, which the owner writes
//! while it holds the lock and removes before it lets go).
//!
//! Within one process the lock is re-entrant: a command that takes it and then calls a library
//! function that takes it again (a stability run's sweep, a figure's plot) shares it; it is let
//! go when the last holder is dropped.

use super::OutputError;
use fs4::fs_std::FileExt;
use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The file naming the owner of a locked directory.
pub const LOCK_FILE: &str = ".magbubble.lock";

/// The directories this process holds: (canonical path, holders, the locked directory handle).
static HELD: Mutex<Vec<(PathBuf, usize, File)>> = Mutex::new(Vec::new());

/// This process's hold on an output directory; dropping the last one releases it.
#[derive(Debug)]
pub struct DirLock {
    key: PathBuf,
}

impl DirLock {
    /// Takes the lock on `dir`, creating the directory (and its parents) when it is missing.
    pub fn acquire(dir: &Path) -> Result<DirLock, OutputError> {
        let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
        fs::create_dir_all(dir).map_err(|source| OutputError::CreateDir { path: dir.display().to_string(), source })?;
        let key = fs::canonicalize(dir).map_err(|source| OutputError::CreateDir { path: dir.display().to_string(), source })?;
        let mut held = HELD.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(entry) = held.iter_mut().find(|e| e.0 == key) {
            entry.1 += 1;
            return Ok(DirLock { key });
        }
        let handle = File::open(&key).map_err(|source| OutputError::Write { path: key.display().to_string(), source })?;
        match handle.try_lock_exclusive() {
            Ok(true) => {}
            Ok(false) => {
                let owner = fs::read_to_string(key.join(LOCK_FILE)).ok().and_then(|t| t.trim().parse::<u32>().ok());
                return Err(OutputError::Busy { path: dir.display().to_string(), owner });
            }
            Err(source) => return Err(OutputError::Write { path: key.display().to_string(), source }),
        }
        let pid_file = key.join(LOCK_FILE);
        fs::write(&pid_file, format!("{}\n", std::process::id()))
            .map_err(|source| OutputError::Write { path: pid_file.display().to_string(), source })?;
        held.push((key.clone(), 1, handle));
        Ok(DirLock { key })
    }

    /// The locked directory (canonical).
    pub fn path(&self) -> &Path {
        &self.key
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        let mut held = HELD.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(i) = held.iter().position(|e| e.0 == self.key) {
            held[i].1 -= 1;
            if held[i].1 == 0 {
                // the owner's note goes first, while the lock is still held
                let _ = fs::remove_file(self.key.join(LOCK_FILE));
                let (_, _, handle) = held.swap_remove(i);
                let _ = FileExt::unlock(&handle);
            }
        }
    }
}

/// Whether `name` is the lock's own file (not an output: listings of a directory skip it).
pub fn is_lock_file(name: &std::ffi::OsStr) -> bool {
    name == LOCK_FILE
}
