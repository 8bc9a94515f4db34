//! Issue 15 property "results identical across thread counts" for `figure` (stability has it:
//! stability_sweep.rs): the stability figures at reduced resolution (`--quick`) run with
//! RAYON_NUM_THREADS = 1 and 2 write byte-identical CSV, SVG and PNG files. Each curve point is
//! a pure function of its parameters and rows are written in index order, so the thread count may
//! change the wall time only (the figNN.md notes differ in their timing lines, nothing else).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// Every file `figure N --quick` writes with `threads` rayon threads: name → bytes.
fn figure(n: u32, threads: usize, out: &Path) -> BTreeMap<String, Vec<u8>> {
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["figure", &n.to_string(), "--quick", "--out"])
        .arg(out)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .unwrap();
    assert!(o.status.success(), "figure {n} with {threads} threads:\n{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_dir(out)
        .unwrap()
        .flatten()
        // figNN.parts/ (the finished curves kept for a resume) is a directory: files only.
        .filter(|e| e.path().is_file())
        .map(|e| (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap()))
        .collect()
}

#[test]
fn stability_figures_are_identical_with_one_and_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    for n in [5, 6, 7, 9, 10, 11] {
        let one = figure(n, 1, &tmp.path().join(format!("{n}-1")));
        let two = figure(n, 2, &tmp.path().join(format!("{n}-2")));
        assert_eq!(one.keys().collect::<Vec<_>>(), two.keys().collect::<Vec<_>>(), "figure {n}: different files");
        let mut compared = 0;
        for (name, bytes) in &one {
            if name.ends_with(".md") {
                // the note differs in its timings only: the total line and the table's last column
                let strip = |b: &[u8]| -> Vec<String> {
                    let text = String::from_utf8_lossy(b).into_owned();
                    text.lines()
                        .filter(|l| !l.starts_with("- total wall time"))
                        .map(|l| if l.starts_with("| ") { l.trim_end_matches('|').rsplit_once('|').map_or(l, |(a, _)| a).to_string() } else { l.to_string() })
                        .collect()
                };
                assert_eq!(strip(bytes), strip(&two[name]), "figure {n}: {name}");
                continue;
            }
            assert!(bytes == &two[name], "figure {n}: {name} differs between 1 and 2 threads");
            compared += 1;
        }
        assert!(one.keys().any(|k| k.ends_with(".csv")) && compared >= 3, "figure {n}: {:?}", one.keys());
        eprintln!("figure {n}: {compared} CSV/SVG/PNG files identical with 1 and 2 threads");
    }
}
