//! The blow-up time is located on the dense output (issue 16 part 4), so it does not depend on
//! `run.sample_interval`: coil_static (fig 12, a16 crosses the threshold near 20.6 µs) sampled
//! every 10 ns, 100 ns and 1 µs must report the same time to 1e-6 relative, and the last sample
//! (the state at the crossing) must be no later than it.

use magbubble::model::{simulate, RunStatus};
use magbubble::scene;
use std::path::PathBuf;

fn blow_up_at(sample: &str) -> (f64, String, f64) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/coil_static.toml");
    let s = scene::load(path, &[format!("run.sample_interval={sample}"), "run.duration=30e-6".into()]).expect("scene");
    let mut last = 0.0;
    let report = simulate(&s, &mut |t, _| last = t).expect("model");
    match report.status {
        RunStatus::BlowUp { t, mode } => (t, mode, last),
        other => panic!("sample {sample}: expected a blow-up, got {other:?}"),
    }
}

#[test]
fn blow_up_time_does_not_depend_on_the_sample_interval() {
    let (t_fine, mode, last) = blow_up_at("1e-8");
    assert_eq!(mode, "a16");
    assert!(t_fine > 15e-6 && t_fine < 25e-6, "{t_fine}");
    assert!(last <= t_fine * (1.0 + 1e-12), "last sample {last} after the crossing {t_fine}");
    for sample in ["1e-7", "1e-6"] {
        let (t, m, _) = blow_up_at(sample);
        assert_eq!(m, mode, "sample {sample}");
        assert!(((t - t_fine) / t_fine).abs() < 1e-6, "sample {sample}: {t} vs {t_fine}");
    }
}
