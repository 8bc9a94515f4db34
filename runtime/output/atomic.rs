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

    /// Flushes and renames the temp file to the final path. On any error (a full disk shows at
    /// the last flush) the temp file is removed: nothing temporary survives.
    ///
    /// No `fsync`: the rename alone is what a reader needs — another process (or this run
    /// killed half-way) sees the old file or the whole new one, never a partial one. A sync
    /// would only add durability across an operating-system crash or power loss in the
    /// seconds before the kernel writes the page cache back, for output any run reproduces;
    /// it cost 2 syncs per run, a short run's wall 3–8× its CPU (issue 34,
    /// docs/performance.md "Radial runs against APECSS"). The sweep's resume checkpoint
    /// (analysis/sweep.rs), which hours of work depend on, keeps its sync.
    pub fn commit(mut self) -> Result<(), OutputError> {
        let err = |source| OutputError::Write {
            path: self.path.display().to_string(),
            source,
        };
        let writer = self.writer.take().expect("writer present until commit");
        let result = writer
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|file| {
                drop(file);
                fs::rename(&self.tmp, &self.path)
            });
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

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn the_old_file_stays_whole_until_commit_then_the_new_one_is_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("series.csv");
        fs::write(&path, "old\n").unwrap();
        let mut f = AtomicFile::create(&path).unwrap();
        // more than the write buffer, so part of it already sits in the temp file
        let body = "x".repeat(WRITE_BUFFER + 12345);
        f.write_all(body.as_bytes()).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "old\n", "a reader sees the old file");
        assert_eq!(names(dir.path()), ["series.csv", "series.csv.tmp"]);
        f.commit().unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), body, "the whole new file");
        assert_eq!(names(dir.path()), ["series.csv"], "no temp file left");
    }

    #[test]
    fn dropped_without_commit_leaves_the_old_file_and_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        fs::write(&path, "old").unwrap();
        {
            let mut f = AtomicFile::create(&path).unwrap();
            f.write_all(&vec![b'y'; WRITE_BUFFER * 2]).unwrap();
            // an error on the way: the file is dropped, not committed
        }
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(names(dir.path()), ["summary.json"]);
        // and a new path never appears at all
        let fresh = dir.path().join("new.csv");
        drop(AtomicFile::create(&fresh).unwrap());
        assert!(!fresh.exists());
        assert_eq!(names(dir.path()), ["summary.json"]);
    }

    #[test]
    fn a_failed_rename_removes_the_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        // the final path is a non-empty directory: the rename fails after the data is written
        let path = dir.path().join("out");
        fs::create_dir(&path).unwrap();
        fs::write(path.join("keep"), "k").unwrap();
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(b"data").unwrap();
        assert!(f.commit().is_err());
        assert_eq!(names(dir.path()), ["out"], "no out.tmp left");
        assert_eq!(fs::read_to_string(path.join("keep")).unwrap(), "k");
    }
}
