use magbubble::model::Model;
use magbubble::integrate::OdeSystem;
fn main() {
    let s = magbubble::scene::load("scenes/coil_static.toml", &["drive.amplitude=0.2"]).unwrap();
    let m = Model::from_scene(&s).unwrap();
    let sys = m.system();
    let n = sys.dim();
    let mut y = m.initial_state().to_vec();
    for (i, v) in y.iter_mut().enumerate() { *v += 1e-3 * ((i * 7 % 5) as f64 + 1.0); }
    let mut f0 = vec![0.0; n]; sys.rhs(0.3, &y, &mut f0);
    let mut f1 = vec![0.0; n];
    for i in 0..n { let mut line = String::new();
      for j in 0..n { let mut yy = y.clone(); yy[j] += 1e-7; sys.rhs(0.3, &yy, &mut f1);
        let d = (f1[i]-f0[i])/1e-7; line.push(if d == 0.0 {'.'} else if d.abs() < 1e-10 * (1.0+f0[i].abs()) {'o'} else {'X'}); }
      println!("{line}"); }
}
