//! The seam report counts welded positions whose objects disagree on skin influences.

use glam::Vec3;
use seamlit_mesh::{Influences, Model, Object, ReportOptions, SkinSeamExample, report};

/// A quad over `[x0, x0 + 1] x [0, 1]`, skinned to joints 3 and 8: vertex weights
/// `(w, 1 - w)` with `w` from `weights` in vertex order (0, 0), (1, 0), (1, 1), (0, 1).
fn quad(name: &str, x0: f32, weights: [f32; 4]) -> Object {
    let positions = vec![
        Vec3::new(x0, 0.0, 0.0),
        Vec3::new(x0 + 1.0, 0.0, 0.0),
        Vec3::new(x0 + 1.0, 1.0, 0.0),
        Vec3::new(x0, 1.0, 0.0),
    ];
    let mut object = Object::new(name, positions, vec![[0, 1, 2], [0, 2, 3]]);
    object.skin = vec![Influences {
        joints: vec![[3, 8, 0, 0]; 4],
        weights: weights.iter().map(|&w| [w, 1.0 - w, 0.0, 0.0]).collect(),
    }];
    object
}

/// The left quad's right edge (its vertices 1 and 2) is the right quad's left edge (0 and 3).
fn two_quads(right_weights: [f32; 4]) -> Model {
    Model::new(vec![quad("arm", 0.0, [0.2, 0.6, 0.7, 0.2]), quad("shoulder", 1.0, right_weights)])
}

#[test]
fn matching_influences_at_the_seam_count_nothing() {
    // Within a normalised byte's step (1/255) is a match.
    let r =
        report(&two_quads([0.6 + 0.5 / 255.0, 0.9, 0.1, 0.7]), &ReportOptions::default()).unwrap();
    assert_eq!(r.shared_positions, 2);
    assert_eq!(r.skin_seams.positions, 0);
    assert_eq!(r.skin_seams.example, None);
}

#[test]
fn one_seam_vertex_with_other_weights_is_counted_with_its_place_and_objects() {
    // At (1, 1) the shoulder's vertex 3 has 0.5 where the arm has 0.7.
    let r = report(&two_quads([0.6, 0.9, 0.1, 0.5]), &ReportOptions::default()).unwrap();
    assert_eq!(r.skin_seams.positions, 1);
    let expected = SkinSeamExample {
        position: [1.0, 1.0, 0.0],
        objects: ["arm".to_owned(), "shoulder".to_owned()],
    };
    assert_eq!(r.skin_seams.example, Some(expected));
}

#[test]
fn other_joints_or_no_skin_at_all_differ() {
    let mut model = two_quads([0.6, 0.9, 0.1, 0.7]);
    // Same weights, other joints (another skin's nodes) at both seam vertices.
    model.objects[1].skin[0].joints = vec![[4, 8, 0, 0]; 4];
    assert_eq!(report(&model, &ReportOptions::default()).unwrap().skin_seams.positions, 2);
    // A static object welded to a skinned one: the skinned side moves away from it.
    model.objects[1].skin.clear();
    assert_eq!(report(&model, &ReportOptions::default()).unwrap().skin_seams.positions, 2);
}
