//! Sweeps that scale: a parallel map over the points of a sweep (frequencies), written as one CSV
//! row per point, resumable, shardable across a cluster job array, and mergeable.
//!
//! * **Deterministic**: a point's row depends only on the point (never on another point or on
//!   the thread that ran it); the final CSV is sorted by `index`, so it is byte-identical for any
//!   thread count and for any shard split once merged.
//! * **Resume**: each finished row is appended and flushed at once. Re-running the same sweep
//!   into the same file skips the indices already there (a torn last line is discarded). A
//!   sidecar `<csv>.meta.json` records the sweep's fingerprint; a different sweep refuses to
//!   append to it.
//! * **Shards**: shard `i/n` (0 ≤ i < n) owns the points with `index % n == i` (interleaved, so
//!   expensive high-frequency points spread evenly). Default from `SLURM_ARRAY_TASK_ID` (minus
//!   `SLURM_ARRAY_TASK_MIN` when set) and `SLURM_ARRAY_TASK_COUNT`.
//! * **Merge**: [`merge`] joins shard CSVs after checking that they come from the same sweep and
//!   that their indices are non-overlapping and complete.

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs::{self, File, OpenOptions};
use std::io::{BufRead, BufReader, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Errors of a sweep or a merge: which file, which index, why.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error("invalid shard '{text}': expected i/n with 0 ≤ i < n (e.g. 0/4)")]
    BadShard { text: String },
    #[error("environment variable {name}='{value}' is not a valid shard number")]
    BadShardEnv { name: &'static str, value: String },
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {why}")]
    Corrupt { path: PathBuf, why: String },
    #[error("{path} belongs to a different sweep ({why}); choose another output directory or remove it")]
    Mismatch { path: PathBuf, why: String },
    #[error("merge: {why}")]
    Merge { why: String },
    /// The output directory is another process's ([`crate::output::DirLock`]).
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io { path: path.to_path_buf(), source }
}

/// One deterministic slice of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `i/n`.
    pub fn parse(text: &str) -> Result<Shard, SweepError> {
        let bad = || SweepError::BadShard { text: text.to_string() };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The shard of a SLURM job array task, when `SLURM_ARRAY_TASK_ID` and
    /// `SLURM_ARRAY_TASK_COUNT` are set (index = ID − `SLURM_ARRAY_TASK_MIN`, default MIN 0).
    pub fn from_env() -> Result<Option<Shard>, SweepError> {
        Self::from_vars(|k| std::env::var(k).ok())
    }

    /// [`from_env`](Self::from_env) with an explicit variable lookup (testable).
    pub fn from_vars(get: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, SweepError> {
        let num = |name: &'static str| -> Result<Option<usize>, SweepError> {
            match get(name) {
                None => Ok(None),
                Some(v) => v.trim().parse().map(Some).map_err(|_| SweepError::BadShardEnv { name, value: v }),
            }
        };
        let (Some(id), Some(count)) = (num("SLURM_ARRAY_TASK_ID")?, num("SLURM_ARRAY_TASK_COUNT")?) else {
            return Ok(None);
        };
        let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let text = format!("{}/{}", id.wrapping_sub(min), count);
        if id < min {
            return Err(SweepError::BadShard { text });
        }
        Shard::parse(&text).map(Some)
    }

    pub fn owns(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

/// The sidecar metadata of a sweep CSV.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepMeta {
    /// What was computed (scene, method, ranges…): two files merge only if these are equal.
    pub fingerprint: String,
    /// Number of points of the whole (unsharded) sweep.
    pub total: usize,
    pub shard: Shard,
    pub header: Vec<String>,
}

/// The sidecar path of a sweep CSV.
pub fn meta_path(csv: &Path) -> PathBuf {
    let mut s = csv.as_os_str().to_owned();
    s.push(".meta.json");
    PathBuf::from(s)
}

/// What [`run`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepReport {
    /// Rows of this shard, sorted by index (index, fields without the index).
    pub rows: Vec<(usize, Vec<String>)>,
    pub computed: usize,
    pub resumed: usize,
    /// Whether [`Control::cancel`] stopped the sweep before every point was done (the rows
    /// are then the whole rows finished so far; a rerun resumes).
    pub cancelled: bool,
}

/// `retry(index, fields)`: whether a finished row is computed again instead of resumed.
pub type RetryFn<'a> = dyn Fn(usize, &[String]) -> bool + 'a;

/// How [`run_with`] is driven, beyond the sweep itself (all optional).
#[derive(Clone, Copy, Default)]
pub struct Control<'a> {
    /// Draw a progress bar on stderr when it is a terminal.
    pub progress_bar: bool,
    /// Checked before each point starts: once set, no new point starts, the rows finished so
    /// far are kept (whole) and [`SweepReport::cancelled`] is set.
    pub cancel: Option<&'a AtomicBool>,
    /// Called after each finished point with (points finished in this call, points this call
    /// computes), from the worker thread that finished it.
    pub on_point: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    /// A finished row for which `retry(index, fields)` holds (an error row) is computed again
    /// instead of being resumed.
    pub retry: Option<&'a RetryFn<'a>>,
}

/// Runs `compute(index)` for every index of `shard` in 0..meta.total that is not already in
/// `csv`, in parallel (the current rayon pool), appending each row as soon as it is done; then
/// rewrites the file sorted by index. `header` (in `meta`) excludes the leading `index` column.
pub fn run<F>(csv: &Path, meta: &SweepMeta, progress: bool, compute: F) -> Result<SweepReport, SweepError>
where
    F: Fn(usize) -> Vec<String> + Sync,
{
    run_retrying(csv, meta, progress, |_| false, compute)
}

/// [`run`], where a finished row for which `retry(fields)` holds (an error row) is computed
/// again instead of being resumed.
pub fn run_retrying<F, R>(
    csv: &Path,
    meta: &SweepMeta,
    progress: bool,
    retry: R,
    compute: F,
) -> Result<SweepReport, SweepError>
where
    F: Fn(usize) -> Vec<String> + Sync,
    R: Fn(&[String]) -> bool,
{
    let retry = |_: usize, fields: &[String]| retry(fields);
    let control = Control { progress_bar: progress, retry: Some(&retry), ..Control::default() };
    run_with(Some(csv), meta, &control, |i| Some(compute(i)))
}

/// The general form of [`run`]: `csv` may be `None` (rows kept in memory only), `control` adds
/// cancellation, a progress callback and retried rows, and `compute` may return `None` for a
/// point it gave up on because of the cancel flag (no row is written for it).
pub fn run_with<F>(csv: Option<&Path>, meta: &SweepMeta, control: &Control, compute: F) -> Result<SweepReport, SweepError>
where
    F: Fn(usize) -> Option<Vec<String>> + Sync,
{
    let full_header = header_line(&meta.header);
    let mut done: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    let mut file = None;
    // one process at a time in the CSV's directory, before the CSV is even looked at
    let _lock = match csv {
        Some(csv) => Some(crate::output::DirLock::acquire(csv.parent().unwrap_or(Path::new("")))?),
        None => None,
    };
    if let Some(csv) = csv {
        if csv.exists() {
            let old = read_meta(csv)?;
            if old != *meta {
                let why = if old.fingerprint != meta.fingerprint {
                    "fingerprint differs".to_string()
                } else {
                    format!("shard {}/{} or size {} differs", old.shard.index, old.shard.count, old.total)
                };
                return Err(SweepError::Mismatch { path: csv.to_path_buf(), why });
            }
            done = read_rows(csv, &full_header)?;
            if let Some(retry) = control.retry {
                done.retain(|&i, fields| !retry(i, fields));
            }
        } else if let Some(dir) = csv.parent().filter(|d| !d.as_os_str().is_empty()) {
            fs::create_dir_all(dir).map_err(io(dir))?;
        }
        write_atomic(&meta_path(csv), &serde_json::to_string_pretty(meta).expect("meta serialises"))?;
        // Rewrite what is valid (drops a torn last line), then append.
        write_atomic(csv, &render(&full_header, &done))?;
        file = Some(OpenOptions::new().append(true).open(csv).map_err(io(csv))?);
    }
    let resumed = done.len();
    // the shard's own points only (never a pass over the whole grid: issue 29 item 7)
    let pending: Vec<usize> =
        (meta.shard.index..meta.total).step_by(meta.shard.count.max(1)).filter(|i| !done.contains_key(i)).collect();
    let sink = Mutex::new((file, Vec::<(usize, Vec<String>)>::new()));
    let bar = if control.progress_bar && std::io::stderr().is_terminal() {
        let b = ProgressBar::new(pending.len() as u64);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} points  {elapsed} (eta {eta})") {
            b.set_style(style);
        }
        b
    } else {
        ProgressBar::hidden()
    };
    let (cancel, on_point) = (control.cancel, control.on_point);
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let failure: Mutex<Option<SweepError>> = Mutex::new(None);
    pending.par_iter().for_each(|&i| {
        if cancelled() {
            return;
        }
        let Some(fields) = compute(i) else { return };
        let mut guard = sink.lock().unwrap_or_else(|p| p.into_inner());
        if let (Some(f), Some(csv)) = (guard.0.as_mut(), csv) {
            // One write per row: an interrupted process leaves whole rows (or one torn last
            // line, which the next run discards).
            let res = f.write_all(row_line(i, &fields).as_bytes()).and_then(|_| f.flush());
            if let Err(e) = res {
                failure.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(SweepError::Io { path: csv.to_path_buf(), source: e });
            }
        }
        guard.1.push((i, fields));
        let finished = guard.1.len();
        drop(guard);
        bar.inc(1);
        if let Some(f) = on_point {
            f(finished, pending.len());
        }
    });
    bar.finish_and_clear();
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    let (_, fresh) = sink.into_inner().unwrap_or_else(|p| p.into_inner());
    let computed = fresh.len();
    done.extend(fresh);
    if let Some(csv) = csv {
        write_atomic(csv, &render(&full_header, &done))?;
    }
    let cancelled = computed < pending.len();
    Ok(SweepReport { rows: done.into_iter().collect(), computed, resumed, cancelled })
}

/// Joins shard CSVs (each with its sidecar) into `output` (+ sidecar, shard 0/1), after checking
/// that they are of the same sweep, non-overlapping and complete.
pub fn merge(inputs: &[PathBuf], output: &Path) -> Result<SweepMeta, SweepError> {
    let Some(first) = inputs.first() else {
        return Err(SweepError::Merge { why: "no input files".into() });
    };
    for path in inputs {
        if same_file(path, output) || same_file(&meta_path(path), &meta_path(output)) {
            return Err(SweepError::Merge {
                why: format!("--out {} is one of the inputs; merge into a new file", output.display()),
            });
        }
    }
    let merge_err = |why: String| SweepError::Merge { why };
    for path in inputs {
        if !path.is_file() {
            return Err(merge_err(format!(
                "{}: no such file; give the shard CSVs (NAME.shard-i-of-n.csv, each with its .meta.json) that `stability` or `sweep` with --shard wrote",
                path.display()
            )));
        }
        if !meta_path(path).is_file() {
            return Err(merge_err(format!(
                "{} has no {}: every shard CSV is written with this sidecar (the sweep's fingerprint and split); without it the file cannot be checked: run that shard again",
                path.display(),
                meta_path(path).display()
            )));
        }
    }
    let meta0 = read_meta(first)?;
    let full_header = header_line(&meta0.header);
    let mut rows: BTreeMap<usize, (Vec<String>, PathBuf)> = BTreeMap::new();
    for path in inputs {
        let meta = read_meta(path)?;
        if meta.fingerprint != meta0.fingerprint || meta.total != meta0.total || meta.header != meta0.header {
            return Err(SweepError::Merge {
                why: format!("{} and {} are not shards of the same sweep", first.display(), path.display()),
            });
        }
        if meta.shard.count != meta0.shard.count {
            return Err(merge_err(format!(
                "{} is shard {}/{} and {} is shard {}/{}: shards of different splits overlap; merge the shards of one split (all …/{} or all …/{})",
                first.display(),
                meta0.shard.index,
                meta0.shard.count,
                path.display(),
                meta.shard.index,
                meta.shard.count,
                meta0.shard.count,
                meta.shard.count
            )));
        }
        let got = read_rows(path, &full_header).map_err(|e| match e {
            SweepError::Mismatch { path, why } | SweepError::Corrupt { path, why } => merge_err(format!(
                "{} is damaged ({why}): run its shard {}/{} again (finished rows are kept)",
                path.display(),
                meta.shard.index,
                meta.shard.count
            )),
            other => other,
        })?;
        let owned = (meta.shard.index..meta.total).step_by(meta.shard.count.max(1)).count();
        if got.len() < owned {
            return Err(merge_err(format!(
                "{} holds {} of the {owned} points of shard {}/{}{}: run that shard again to finish it (resume is automatic)",
                path.display(),
                got.len(),
                meta.shard.index,
                meta.shard.count,
                if fs::metadata(path).map(|m| m.len() == 0).unwrap_or(false) { " (the file is empty)" } else { " (truncated or unfinished)" }
            )));
        }
        for (i, fields) in got {
            if i >= meta0.total {
                return Err(SweepError::Merge { why: format!("{}: index {i} ≥ {} points", path.display(), meta0.total) });
            }
            if let Some((_, other)) = rows.insert(i, (fields, path.clone())) {
                return Err(SweepError::Merge {
                    why: format!("index {i} appears in both {} and {}", other.display(), path.display()),
                });
            }
        }
    }
    let missing: Vec<usize> = (0..meta0.total).filter(|i| !rows.contains_key(i)).collect();
    if !missing.is_empty() {
        let shown: Vec<String> = missing.iter().take(20).map(|i| i.to_string()).collect();
        return Err(SweepError::Merge {
            why: format!(
                "incomplete: {} of {} points missing (indices {}{}); run the missing shards (resume is automatic)",
                missing.len(),
                meta0.total,
                shown.join(", "),
                if missing.len() > 20 { ", …" } else { "" }
            ),
        });
    }
    let rows: BTreeMap<usize, Vec<String>> = rows.into_iter().map(|(i, (f, _))| (i, f)).collect();
    let meta = SweepMeta { shard: Shard::ALL, ..meta0 };
    let _lock = crate::output::DirLock::acquire(output.parent().unwrap_or(Path::new("")))?;
    write_atomic(output, &render(&full_header, &rows))?;
    write_atomic(&meta_path(output), &serde_json::to_string_pretty(&meta).expect("meta serialises"))?;
    Ok(meta)
}

/// Whether two paths name the same file (either may not exist yet).
fn same_file(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Reads the sidecar of a sweep CSV.
pub fn read_meta(csv: &Path) -> Result<SweepMeta, SweepError> {
    let mp = meta_path(csv);
    let text = fs::read_to_string(&mp).map_err(io(&mp))?;
    serde_json::from_str(&text).map_err(|e| SweepError::Corrupt { path: mp, why: e.to_string() })
}

fn header_line(header: &[String]) -> String {
    let mut h = vec!["index".to_string()];
    h.extend(header.iter().cloned());
    h.join(",")
}

fn sanitize(field: &str) -> String {
    field.replace([',', '\n', '\r'], ";")
}

fn row_line(index: usize, fields: &[String]) -> String {
    let mut s = index.to_string();
    for f in fields {
        s.push(',');
        s.push_str(&sanitize(f));
    }
    s.push('\n');
    s
}

fn render(header: &str, rows: &BTreeMap<usize, Vec<String>>) -> String {
    let mut s = format!("{header}\n");
    for (i, f) in rows {
        s.push_str(&row_line(*i, f));
    }
    s
}

/// Complete rows of a sweep CSV (a last line without its newline is a torn write and ignored).
pub fn read_rows(csv: &Path, header: &str) -> Result<BTreeMap<usize, Vec<String>>, SweepError> {
    let file = File::open(csv).map_err(io(csv))?;
    let mut reader = BufReader::new(file);
    let mut rows = BTreeMap::new();
    let mut line = String::new();
    let mut lineno = 0;
    let ncols = header.split(',').count();
    loop {
        line.clear();
        let n = reader.read_line(&mut line).map_err(io(csv))?;
        if n == 0 || !line.ends_with('\n') {
            break;
        }
        lineno += 1;
        let text = line.trim_end_matches(['\n', '\r']);
        if lineno == 1 {
            if text != header {
                return Err(SweepError::Mismatch {
                    path: csv.to_path_buf(),
                    why: format!("header '{text}' differs from '{header}'"),
                });
            }
            continue;
        }
        let mut parts = text.split(',');
        let idx = parts.next().and_then(|s| s.parse::<usize>().ok()).ok_or_else(|| SweepError::Corrupt {
            path: csv.to_path_buf(),
            why: format!("line {lineno}: no index in '{text}'"),
        })?;
        let fields: Vec<String> = parts.map(str::to_string).collect();
        if fields.len() + 1 != ncols {
            return Err(SweepError::Corrupt {
                path: csv.to_path_buf(),
                why: format!("line {lineno}: {} columns, header has {ncols}", fields.len() + 1),
            });
        }
        rows.insert(idx, fields);
    }
    Ok(rows)
}

/// Writes `text` to `path` through a temporary file in the same directory and a rename.
fn write_atomic(path: &Path, text: &str) -> Result<(), SweepError> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let written = File::create(&tmp).and_then(|mut f| {
        f.write_all(text.as_bytes())?;
        f.sync_all()
    });
    // nothing temporary survives an error (a full disk, issue 29 item 8)
    if let Err(e) = written.and_then(|()| fs::rename(&tmp, path)) {
        let _ = fs::remove_file(&tmp);
        return Err(io(path)(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parsing() {
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
        for bad in ["4/4", "1", "a/2", "0/0", "-1/3"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |k: &str| pairs.iter().find(|(n, _)| *n == k).map(|(_, v)| v.to_string())
        };
        assert_eq!(Shard::from_vars(env(&[])).unwrap(), None);
        assert_eq!(
            Shard::from_vars(env(&[("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_COUNT", "3")])).unwrap(),
            Some(Shard { index: 2, count: 3 })
        );
        assert_eq!(
            Shard::from_vars(env(&[
                ("SLURM_ARRAY_TASK_ID", "3"),
                ("SLURM_ARRAY_TASK_COUNT", "3"),
                ("SLURM_ARRAY_TASK_MIN", "1")
            ]))
            .unwrap(),
            Some(Shard { index: 2, count: 3 })
        );
        assert!(Shard::from_vars(env(&[("SLURM_ARRAY_TASK_ID", "x"), ("SLURM_ARRAY_TASK_COUNT", "3")])).is_err());
    }
}
