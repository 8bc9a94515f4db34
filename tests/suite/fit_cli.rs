//! `magbubble fit` on the command line (issue 32): the files it writes, and bad input — data
//! outside the run's window, non-monotone or duplicated t, NaN, a non-numeric or unknown key,
//! reversed bounds, a key given twice — each a clear error naming it, with nothing written.

use std::path::Path;
use std::process::Command;

fn setup(dir: &Path) {
    std::fs::write(dir.join("s.toml"), super::fit::scene_text("")).unwrap();
    // data on the run's grid from `run` itself
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble"))
        .args(["run", "s.toml", "--out", "run"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let series = std::fs::read_to_string(dir.join("run/series.csv")).unwrap();
    let mut data = String::from("t,R,a2\n");
    for line in series.lines().skip(1) {
        let v: Vec<&str> = line.split(',').collect();
        data.push_str(&format!("{},{},{}\n", v[0], v[1], v[2]));
    }
    std::fs::write(dir.join("data.csv"), data).unwrap();
}

fn fit(dir: &Path, args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbubble")).arg("fit").args(args).current_dir(dir).output().unwrap();
    (o.status.success(), format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)))
}

#[test]
fn writes_fit_json_csv_and_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    let (ok, out) = fit(dir, &["s.toml", "--data", "data.csv", "--param", "shell.c1=0.01:1", "--set", "shell.c1=0.13", "--out", "f", "--plot"]);
    assert!(ok, "{out}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("f/fit.json")).unwrap()).unwrap();
    for field in ["parameters", "correlation", "residual_rms", "iterations", "status", "warnings"] {
        assert!(json.get(field).is_some(), "fit.json lacks {field}");
    }
    let p = &json["parameters"][0];
    for field in ["key", "value", "std_error", "low", "high"] {
        assert!(p.get(field).is_some(), "parameters[0] lacks {field}");
    }
    assert_eq!(json["status"], "converged");
    // noise-free data from the run: c1 back to 1e-6
    assert!((p["value"].as_f64().unwrap() - 0.1).abs() < 1e-6 * 0.1, "{p}");
    let csv = std::fs::read_to_string(dir.join("f/fit.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), "t,R_data,R_model,R_residual,a2_data,a2_model,a2_residual");
    assert!(dir.join("f/fit.svg").exists());
}

#[test]
fn bad_input_names_it_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    setup(dir);
    let good = std::fs::read_to_string(dir.join("data.csv")).unwrap();
    let lines: Vec<String> = good.lines().map(String::from).collect();
    let write = |name: &str, text: String| std::fs::write(dir.join(name), text).unwrap();
    // outside the window: shifted past run.duration
    write(
        "late.csv",
        std::iter::once("t,R".to_string())
            .chain(lines[1..].iter().map(|l| {
                let v: Vec<&str> = l.split(',').collect();
                format!("{},{}", v[0].parse::<f64>().unwrap() + 1e-6, v[1])
            }))
            .collect::<Vec<_>>()
            .join("\n"),
    );
    let swapped = {
        let mut l = lines.clone();
        l.swap(3, 4);
        l.join("\n")
    };
    write("swapped.csv", swapped);
    let dup = {
        let mut l = lines.clone();
        l.insert(4, l[4].clone());
        l.join("\n")
    };
    write("dup.csv", dup);
    let nan: Vec<String> = good
        .lines()
        .enumerate()
        .map(|(i, l)| if i == 5 { let v: Vec<&str> = l.split(',').collect(); format!("{},NaN,{}", v[0], v[2]) } else { l.to_string() })
        .collect();
    write("nan.csv", nan.join("\n"));
    let cases: &[(&[&str], &str)] = &[
        (&["--data", "late.csv", "--param", "shell.c1"], "outside the run's time window"),
        (&["--data", "swapped.csv", "--param", "shell.c1"], "not increasing"),
        (&["--data", "dup.csv", "--param", "shell.c1"], "duplicated"),
        (&["--data", "nan.csv", "--param", "shell.c1"], "column R"),
        (&["--data", "data.csv", "--param", "shell.law"], "shell.law"),
        (&["--data", "data.csv", "--param", "shell.c9"], "no scene key `shell.c9`"),
        (&["--data", "data.csv", "--param", "shell.c1=1:0.1"], "reversed"),
        (&["--data", "data.csv", "--param", "shell.c1", "--param", "shell.c1=0:1"], "given twice"),
        (&["--data", "missing.csv", "--param", "shell.c1"], "missing.csv"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["s.toml"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--out", "bad"]);
        let (ok, out) = fit(dir, &all);
        assert!(!ok, "{args:?} should fail");
        assert!(out.contains(needle), "{args:?}: the error should say `{needle}`:\n{out}");
        assert!(!dir.join("bad").exists(), "{args:?}: something was written");
    }
}
