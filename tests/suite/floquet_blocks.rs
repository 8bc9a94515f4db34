//! The field-free Floquet system's mode blocks (issue 16: the monodromy is block diagonal per
//! mode without a field): `linear_mode_blocks_into` gives exactly the diagonal 3 × 3 blocks of
//! the dense A(t) of `linear_modes`, and the dense A has nothing outside them.

use magbubble::model::layout::StateLayout;
use magbubble::model::Model;
use magbubble::scene::load;

#[test]
fn mode_blocks_are_the_dense_matrix() {
    let scenes = [
        load("scenes/no_field.toml", &["modes.max_order=32"]).unwrap(),
        load("scenes/no_field.toml", &["modes.max_order=16", "shell.form=\"tension\"", "shell.bending_modulus=1e-18"]).unwrap(),
        load("scenes/no_field.toml", &["modes.max_order=16", "shell.shear_viscosity=1e-9", "shell.dilatational_viscosity=2e-9"]).unwrap(),
        load("scenes/free_bubble.toml", &["modes.max_order=16", "shell.surface_tension=0.072"]).unwrap(),
    ];
    for (s, scene) in scenes.iter().enumerate() {
        let model = Model::from_scene(scene).unwrap();
        let bl = model.boundary_layer().unwrap();
        assert_eq!(bl.jacobian_pattern().band, 0);
        let nm = bl.modes().len();
        for (t, r, rd, rdd) in [(0.3, 1.1, 0.2, -0.4), (2.0, 0.7, -0.5, 3.0), (5.5, 1.4, 0.05, 0.1)] {
            let (a, _) = bl.linear_modes(t, r, rd, rdd);
            let mut blocks = vec![[0.0; 9]; nm];
            bl.linear_mode_blocks_into(t, r, rd, rdd, &mut blocks);
            let mut nonzero = 0;
            let (mode, entry) = (StateLayout::x_mode, StateLayout::x_entry);
            for i in 0..StateLayout::x_dim(nm) {
                for j in 0..StateLayout::x_dim(nm) {
                    if mode(i) == mode(j) {
                        let b = blocks[mode(i)][entry(j) * StateLayout::AMPLITUDES + entry(i)];
                        assert_eq!(b.to_bits(), a[(i, j)].to_bits(), "scene {s}: A[{i}][{j}] = {} vs block {b}", a[(i, j)]);
                        nonzero += (b != 0.0) as usize;
                    } else {
                        assert_eq!(a[(i, j)], 0.0, "scene {s}: A[{i}][{j}] outside the mode blocks");
                    }
                }
            }
            assert!(nonzero >= 4 * nm, "scene {s}: the blocks are (nearly) empty");
        }
    }
}
