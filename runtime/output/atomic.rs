//! Atomic files (temp file + rename) and output directories that vanish when a run fails.

use super::{DirLock, OutputError};
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Write buffer of an [`AtomicFile`]: 1 MiB, so a series.csv of a few MB goes out in a few
/// `write` calls instead of hundreds of 8 KiB ones (std's default).
const WRITE_BUFFER: usize = 1 << 20;

/// A buffered file written as `NAME.tmp` next to its final path; [`AtomicFile::commit`] flushes
/// and renames it into place. Dropped without commit, the temp file is removed.
#[derive(Debug)]
pub struct AtomicFile {
    tmp: PathBuf,
    path: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let mut name = path
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_default();
        name.push(".tmp");
        let tmp = path.with_file_name(name);
        let file = File::create(&tmp).map_err(|source| OutputError::Write {
            path: tmp.display().to_string(),
            source,
        })?;
        Ok(AtomicFile {
            tmp,
            path: path.to_path_buf(),
            writer: Some(BufWriter::with_capacity(WRITE_BUFFER, file)),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the temp file to the final path. On any error (a full disk
    /// shows at the last flush) the temp file is removed: nothing temporary survives.
    pub fn commit(mut self) -> Result<(), OutputError> {
        let err = |source| OutputError::Write {
            path: self.path.display().to_string(),
            source,
        };
        let writer = self.writer.take().expect("writer present until commit");
        let result = writer
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|file| file.sync_all())
            .and_then(|()| fs::rename(&self.tmp, &self.path));
        if let Err(e) = result {
            let _ = fs::remove_file(&self.tmp);
            return Err(err(e));
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer
            .as_mut()
            .expect("writer present until commit")
            .write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.writer
            .as_mut()
            .expect("writer present until commit")
            .flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// An output directory, remembering whether this run created it, owned by this process while
/// it lives ([`DirLock`]).
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    created: bool,
    lock: Option<DirLock>,
}

impl OutputDir {
    /// Creates `path` (and its parents) if needed and takes its lock (a directory another
    /// process writes into is [`OutputError::Busy`]). Call it only once the inputs are valid.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let created = !path.exists();
        let lock = match DirLock::acquire(path) {
            Ok(l) => l,
            Err(e) => {
                if created {
                    let _ = fs::remove_dir(path);
                }
                return Err(e);
            }
        };
        Ok(OutputDir {
            path: path.to_path_buf(),
            created,
            lock: Some(lock),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `dir/name`.
    pub fn join(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// After a failure: removes the directory if this run created it and it is empty
    /// (temp files are removed by their [`AtomicFile`]s being dropped first).
    pub fn discard(mut self) {
        drop(self.lock.take());
        if self.created {
            let _ = fs::remove_dir(&self.path);
        }
    }
}
