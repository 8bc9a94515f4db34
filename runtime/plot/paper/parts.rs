//! Finished curves of a figure, kept in the output directory so that an interrupted
//! `magbubble figure` resumes instead of starting again (issue 15 "figure resumes finished
//! curves after an interruption").
//!
//! Each curve (a time-series variant, a stability family) is written, once computed, to
//! `OUT/figNN.parts/curve-II.json` (atomically: temp file + rename, so a kill leaves no half
//! file). The file holds a [`PartKey`] — everything the curve's numbers depend on: the figure
//! and curve, the scene file's FNV-1a hash, the overrides, `--quick`, the resolution (frequency
//! grid, search range) and the build (version, executable size and modification time) — and
//! the curve's data with every number written exactly (`{:e}`, the shortest text that parses
//! back to the same f64, NaN and ±inf included), so a resumed figure is byte-identical to an
//! uninterrupted one. A part whose key differs from the request, or that cannot be read, is
//! recomputed and overwritten; `figure --fresh` removes the directory first.

use super::{write_atomic, FigureError};
use crate::plot::PlotError;
use serde::{de::DeserializeOwned, Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Format version of a part file (bump when the payload of a recipe changes).
const FORMAT: u32 = 1;

/// What a curve's numbers depend on; a stored part is reused only when its key is equal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartKey {
    pub format: u32,
    pub figure: u32,
    pub curve: usize,
    pub label: String,
    /// The scene file name and the FNV-1a 64 hash of its bytes (hex).
    pub scene: String,
    pub scene_hash: String,
    pub overrides: Vec<String>,
    pub quick: bool,
    /// The recipe's resolution, e.g. the frequency grid and search range, as text.
    pub resolution: String,
    /// `magbubble <version>`, executable size and modification time.
    pub build: String,
}

impl PartKey {
    /// The key of curve `curve` (`label`) of figure `figure`, run from `scene` with `overrides`.
    pub fn new(
        figure: u32,
        curve: usize,
        label: &str,
        scene: &Path,
        overrides: &[String],
        quick: bool,
        resolution: String,
    ) -> Result<Self, FigureError> {
        let bytes = std::fs::read(scene).map_err(|source| PlotError::Io {
            path: scene.to_path_buf(),
            source,
        })?;
        Ok(Self {
            format: FORMAT,
            figure,
            curve,
            label: label.to_string(),
            scene: scene.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            scene_hash: format!("{:016x}", fnv1a(&bytes)),
            overrides: overrides.to_vec(),
            quick,
            resolution,
            build: build_id(),
        })
    }

    /// The first field in which `self` (stored) differs from `want`, for the message.
    fn differs(&self, want: &PartKey) -> Option<&'static str> {
        let fields: [(&'static str, bool); 10] = [
            ("format", self.format != want.format),
            ("figure", self.figure != want.figure),
            ("curve", self.curve != want.curve),
            ("curve label", self.label != want.label),
            ("scene file", self.scene != want.scene || self.scene_hash != want.scene_hash),
            ("overrides", self.overrides != want.overrides),
            ("--quick", self.quick != want.quick),
            ("resolution", self.resolution != want.resolution),
            ("build", self.build != want.build),
            ("", false),
        ];
        fields.iter().find(|f| f.1).map(|f| f.0)
    }
}

/// FNV-1a, 64 bit: a stable hash of the scene file (not cryptographic; it detects edits).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}

/// `magbubble 0.1.0, <size> bytes, modified <unix seconds>` of the running executable.
fn build_id() -> String {
    let meta = std::env::current_exe().and_then(std::fs::metadata);
    let (len, mtime) = meta.map_or((0, 0), |m| {
        let t = m.modified().ok().and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok());
        (m.len(), t.map_or(0, |d| d.as_secs()))
    });
    format!("magbubble {}, {len} bytes, modified {mtime}", env!("CARGO_PKG_VERSION"))
}

/// How a curve was obtained.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PartUse {
    /// Computed (no stored part).
    Computed,
    /// Read from the stored part (same key).
    Reused,
    /// A stored part was for another request (the field named) or unreadable: computed again.
    Recomputed(String),
}

#[derive(Serialize, Deserialize)]
struct PartFile<T> {
    key: PartKey,
    data: T,
}

/// The parts directory of one figure: `OUT/figNN.parts`.
pub fn parts_dir(out_dir: &Path, stem: &str) -> PathBuf {
    out_dir.join(format!("{stem}.parts"))
}

/// The stored curve for `key` if there is one with this key; else computes it with `make`,
/// stores it and says why it was computed.
pub fn reuse_or<T, E>(
    dir: &Path,
    key: &PartKey,
    make: impl FnOnce() -> Result<T, E>,
) -> Result<(T, PartUse), E>
where
    T: Serialize + DeserializeOwned,
    E: From<FigureError>,
{
    let path = dir.join(format!("curve-{:02}.json", key.curve));
    let mut how = PartUse::Computed;
    if let Ok(text) = std::fs::read_to_string(&path) {
        match serde_json::from_str::<PartFile<T>>(&text) {
            Ok(p) => match p.key.differs(key) {
                None => return Ok((p.data, PartUse::Reused)),
                Some(field) => how = PartUse::Recomputed(format!("the stored part is for another {field}")),
            },
            Err(e) => how = PartUse::Recomputed(format!("the stored part is unreadable ({e})")),
        }
    }
    let data = make()?;
    let file = PartFile { key: key.clone(), data };
    let text = serde_json::to_string(&file).map_err(|e| {
        FigureError::from(PlotError::Csv { path: path.clone(), line: 0, reason: e.to_string() })
    })?;
    write_atomic(&path, text.as_bytes()).map_err(FigureError::from)?;
    Ok((file.data, how))
}

/// Exact text for f64 fields (`#[serde(with = "exact")]`): `{:e}` round-trips, NaN and inf too.
pub mod exact {
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{v:e}"))
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let t = String::deserialize(d)?;
        t.parse().map_err(|_| D::Error::custom(format!("`{t}` is not a number")))
    }
}

/// A `Vec<f64>` as one string of space-separated exact numbers.
pub mod exact_vec {
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn to_text(v: &[f64]) -> String {
        v.iter().map(|x| format!("{x:e}")).collect::<Vec<_>>().join(" ")
    }
    pub fn from_text(t: &str) -> Result<Vec<f64>, String> {
        t.split_ascii_whitespace().map(|w| w.parse().map_err(|_| format!("`{w}` is not a number"))).collect()
    }
    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&to_text(v))
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        from_text(&String::deserialize(d)?).map_err(D::Error::custom)
    }
}

/// A `Vec<Vec<f64>>` as one string per row.
pub mod exact_rows {
    use super::exact_vec::{from_text, to_text};
    use serde::{de::Error, ser::SerializeSeq, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(rows: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(rows.len()))?;
        for r in rows {
            seq.serialize_element(&to_text(r))?;
        }
        seq.end()
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
        let rows = Vec::<String>::deserialize(d)?;
        rows.iter().map(|r| from_text(r).map_err(D::Error::custom)).collect()
    }
}

/// An `Option<Vec<f64>>` (e.g. the multipliers of a family that has none).
pub mod exact_opt_vec {
    use super::exact_vec::{from_text, to_text};
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &Option<Vec<f64>>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.serialize_some(&to_text(v)),
            None => s.serialize_none(),
        }
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<f64>>, D::Error> {
        Option::<String>::deserialize(d)?.map(|t| from_text(&t).map_err(D::Error::custom)).transpose()
    }
}

/// An `Option<(String, f64)>` (a blow-up: mode and time).
pub mod exact_blow_up {
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &Option<(String, f64)>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some((m, t)) => s.serialize_some(&(m, format!("{t:e}"))),
            None => s.serialize_none(),
        }
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<(String, f64)>, D::Error> {
        Option::<(String, String)>::deserialize(d)?
            .map(|(m, t)| t.parse().map(|t| (m, t)).map_err(|_| D::Error::custom(format!("`{t}` is not a number"))))
            .transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Data {
        #[serde(with = "exact_vec")]
        v: Vec<f64>,
        #[serde(with = "exact_rows")]
        rows: Vec<Vec<f64>>,
    }

    #[test]
    fn numbers_round_trip_exactly() {
        let v = vec![0.1 + 0.2, -1e-300, 5e-324, f64::INFINITY, -0.0, 1.0 / 3.0];
        let d = Data { v: v.clone(), rows: vec![v.clone(), vec![]] };
        let back: Data = serde_json::from_str(&serde_json::to_string(&d).unwrap()).unwrap();
        assert_eq!(back, d);
        let nan: Vec<f64> = exact_vec::from_text(&exact_vec::to_text(&[f64::NAN])).unwrap();
        assert!(nan[0].is_nan());
        assert_ne!(fnv1a(b"a = 1"), fnv1a(b"a = 2"));
    }
}
