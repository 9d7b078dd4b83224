//! Scene files parsed and checked: what each table becomes, and the line and column each
//! error names.

use super::*;
use glam::Vec3;

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::parse(text, Path::new("/scenes"), Path::new("/scenes/s.toml"))
}

fn err(text: &str) -> SceneError {
    match parse(text) {
        Ok(s) => panic!("expected an error, got {s:?}"),
        Err(e) => e,
    }
}

/// Whether `e` is a TOML error at `line`, about `key`.
fn parse_error_at(e: &SceneError, at: usize, named: &str) -> bool {
    matches!(e, SceneError::Parse { line, key: Some(key), .. } if *line == at && key == named)
}

/// The kind of an [`SceneError::Invalid`] at `line`.
fn invalid_at(e: &SceneError, at: usize) -> &Invalid {
    match e {
        SceneError::Invalid { line, kind, .. } if *line == at => kind,
        other => panic!("expected an invalid value at line {at}, got {other:?}"),
    }
}

#[test]
fn a_full_scene_resolves_paths_transforms_lights_and_cameras() {
    let scene = parse(
        r#"
[[model]]
path = "teapot.obj"
translate = [1, 2, 3]
rotate = [0, 90, 0]
scale = 2
fix = { mode = "object", crease_angle_deg = 30, normals = "keep" }

[[model.material]]
base_color = [1, 0, 0]
normal_texture = "builtin:bricks"

[[light]]
type = "point"
position = [0, 5, 0]
range = 20

[[camera]]
name = "front"
position = [0, 0, 10]
target = [0, 0, 0]
fov_deg = 50
"#,
    )
    .unwrap();
    let m = &scene.models[0];
    assert_eq!(m.path, Path::new("/scenes/teapot.obj"));
    assert_eq!(m.name, "teapot");
    assert_eq!(m.fix.mode, seamlit_mesh::Mode::Object);
    assert_eq!(m.fix.crease_angle_deg, 30.0);
    assert_eq!(m.fix.normals, seamlit_mesh::NormalPolicy::Keep);
    // Unnamed FixOptions fields keep their defaults.
    assert_eq!(m.fix.weighting, FixOptions::DEFAULT.weighting);
    // Scale 2, then 90 degrees about Y (+X goes to -Z), then translate.
    let p = m.transform.transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5, "{p}");
    assert_eq!(m.materials[0].base_color, Some([1.0, 0.0, 0.0, 1.0]));
    assert_eq!(m.materials[0].normal_texture, Some(NormalTexture::Bricks));
    assert_eq!(
        scene.lights,
        vec![Light::Point {
            position: Vec3::new(0.0, 5.0, 0.0),
            color: Vec3::ONE,
            intensity: 1.0,
            range: 20.0
        }]
    );
    assert_eq!(scene.cameras[0].name, "front");
    assert_eq!(scene.cameras[0].fov_y_deg, 50.0);
}

#[test]
fn an_unknown_key_is_named_with_its_line() {
    let e = err(
        "[[model]]\npath = \"a.obj\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\ncolour = 3\n",
    );
    assert!(matches!(&e, SceneError::Parse { column: 1, .. }), "{e}");
    assert!(parse_error_at(&e, 8, "colour"), "{e:?}");
    // What the user reads: the file, line and column, then toml's message, once.
    let text = e.to_string();
    assert!(text.starts_with("/scenes/s.toml: line 8, column 1: unknown field `colour`"), "{e}");
    assert_eq!(text.matches("unknown field").count(), 1, "{e}");
}

#[test]
fn a_wrong_type_is_named_with_its_key_and_line() {
    let e = err(
        "[[model]]\npath = \"a.obj\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\nfov_deg = \"wide\"\n",
    );
    assert!(parse_error_at(&e, 8, "fov_deg"), "{e:?}");
    assert!(e.to_string().contains("key `fov_deg`"), "{e}");
}

#[test]
fn the_render_table_sets_environment_background_and_tone_mapping() {
    let scene = parse(
        "[[model]]\npath = \"a.obj\"\n[render]\nenvironment = \"sky.hdr\"\n\
         environment_intensity = 2\nenvironment_rotation = 90\nbackground = [1, 0.5, 0]\n\
         ambient = 0\ntone_mapping = \"aces\"\nexposure = 1.5\nshadows = false\n",
    )
    .unwrap();
    let r = &scene.render;
    assert_eq!(r.environment, Some(EnvironmentChoice::File(PathBuf::from("/scenes/sky.hdr"))));
    assert_eq!(r.environment_intensity, Some(2.0));
    assert_eq!(r.environment_rotation_deg, Some(90.0));
    assert_eq!(r.background, Some([1.0, 0.5, 0.0]));
    assert_eq!(r.ambient, Some(0.0));
    assert_eq!(r.tone_mapping, Some(ToneMapping::Aces));
    assert_eq!(r.exposure, Some(1.5));
    assert_eq!(r.shadows, Some(false));
    let builtin = parse("[[model]]\npath = \"a.obj\"\n[render]\nenvironment = \"builtin\"\n");
    assert_eq!(builtin.unwrap().render.environment, Some(EnvironmentChoice::Builtin));
    assert_eq!(parse("[[model]]\npath = \"a.obj\"\n").unwrap().render, RenderOptions::default());
    let e = err("[[model]]\npath = \"a.obj\"\n[render]\nexposure = 0\n");
    assert!(
        matches!(
            invalid_at(&e, 3),
            Invalid::RenderValue { key: "exposure", value: 0.0, expected: "a number > 0" }
        ),
        "{e}"
    );
    let e = err("[[model]]\npath = \"a.obj\"\n[render]\nbackground = [2, 0, 0]\n");
    assert_eq!(invalid_at(&e, 3), &Invalid::Background { value: [2.0, 0.0, 0.0] });
    let e = err("[[model]]\npath = \"a.obj\"\n[render]\ntone_mapping = \"reinhard\"\n");
    assert!(parse_error_at(&e, 4, "tone_mapping"), "{e:?}");
}

#[test]
fn the_render_table_names_an_animation_and_a_time() {
    let named = parse("[[model]]\npath = \"a.glb\"\n[render]\nanimation = \"Walk\"\ntime = 0.5\n");
    let r = named.unwrap().render;
    assert_eq!(r.animation, Some(AnimationChoice::Name("Walk".into())));
    assert_eq!(r.time, Some(0.5));
    let indexed = parse("[[model]]\npath = \"a.glb\"\n[render]\nanimation = 2\n");
    assert_eq!(indexed.unwrap().render.animation, Some(AnimationChoice::Index(2)));
    let e = err("[[model]]\npath = \"a.glb\"\n[render]\ntime = -1\n");
    assert!(
        matches!(
            invalid_at(&e, 3),
            Invalid::RenderValue { key: "time", value: -1.0, expected: "seconds >= 0" }
        ),
        "{e}"
    );
    let e = err("[[model]]\npath = \"a.glb\"\n[render]\nanimation = [1]\n");
    assert!(parse_error_at(&e, 4, "animation"), "{e:?}");
    assert_eq!(AnimationChoice::parse("3"), AnimationChoice::Index(3));
    assert_eq!(AnimationChoice::parse("Run"), AnimationChoice::Name("Run".into()));
}

#[test]
fn a_model_names_its_own_animation_and_time() {
    let scene = parse("[[model]]\npath = \"a.glb\"\nanimation = \"Run\"\ntime = 1.5\n");
    let model = &scene.unwrap().models[0];
    assert_eq!(model.animation, Some(AnimationChoice::Name("Run".into())));
    assert_eq!(model.time, Some(1.5));
    let e = err("[[model]]\npath = \"a.glb\"\ntime = -1\n");
    assert_eq!(invalid_at(&e, 1), &Invalid::ModelTime { model: "a".into(), value: -1.0 });
}

#[test]
fn the_render_table_chooses_the_lighting() {
    let scene = parse("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"pbr\"\n").unwrap();
    assert_eq!(scene.lighting, Some(LightingModel::Pbr));
    let scene =
        parse("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"blinn-phong\"\n").unwrap();
    assert_eq!(scene.lighting, Some(LightingModel::BlinnPhong));
    assert_eq!(parse("[[model]]\npath = \"a.obj\"\n").unwrap().lighting, None);
    let e = err("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"cel\"\n");
    assert!(parse_error_at(&e, 4, "lighting"), "{e:?}");
}

#[test]
fn an_unknown_fix_option_is_an_error() {
    let e = err("[[model]]\npath = \"a.obj\"\n[model.fix]\ncrease = 30\n");
    assert!(parse_error_at(&e, 4, "crease"), "{e:?}");
    let e = err("[[model]]\npath = \"a.obj\"\n[model.fix]\nmode = \"smooth\"\n");
    assert!(parse_error_at(&e, 4, "mode"), "{e:?}");
}

#[test]
fn a_missing_key_is_named() {
    let e = err("[[model]]\npath = \"a.obj\"\n[[camera]]\nposition = [0,0,1]\ntarget = [0,0,0]\n");
    assert!(parse_error_at(&e, 3, "name"), "{e:?}");
}

#[test]
fn bad_values_are_rejected_with_the_line_of_their_table() {
    let cases: [(&str, usize, Invalid); 8] = [
        (
            "[[model]]\npath = \"a\"\n[[light]]\ntype = \"directional\"\n",
            3,
            Invalid::LightNeeds { light: "directional", key: "direction" },
        ),
        (
            "[[model]]\npath = \"a\"\n[[light]]\ntype = \"point\"\nposition = [0,1,0]\ndirection = [0,1,0]\n",
            3,
            Invalid::LightHasNo { light: "point", key: "direction" },
        ),
        (
            "[[model]]\npath = \"a\"\n[[light]]\ntype = \"spot\"\nposition = [0,1,0]\ndirection = [0,-1,0]\ninner_cone_deg = 40\nouter_cone_deg = 30\n",
            3,
            Invalid::Cones { inner_cone_deg: 40.0, outer_cone_deg: 30.0 },
        ),
        (
            "[[model]]\npath = \"a\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\nfov_deg = 0\n",
            4,
            Invalid::FieldOfView { camera: "c".into(), fov_deg: 0.0 },
        ),
        (
            "[[model]]\npath = \"a\"\nscale = [1, 0, 1]\n",
            1,
            Invalid::ZeroScale { model: "a".into() },
        ),
        (
            "[[model]]\npath = \"a\"\n[[model.material]]\nbase_color = [1, 0]\n",
            1,
            Invalid::BaseColorLength { model: "a".into(), found: 2 },
        ),
        (
            "[[model]]\npath = \"a\"\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\n[[camera]]\nname = \"c\"\nposition = [0,0,2]\ntarget = [0,0,0]\n",
            7,
            Invalid::DuplicateCamera { name: "c".into() },
        ),
        ("", 1, Invalid::NoModel),
    ];
    for (text, line, expected) in cases {
        let e = err(text);
        assert_eq!(invalid_at(&e, line), &expected, "{text:?}");
    }
}

#[test]
fn malformed_toml_is_a_parse_error_with_a_position() {
    let e = err("[[model]]\npath = \"a.obj\nx = 1\n");
    assert!(matches!(e, SceneError::Parse { line: 2, .. }), "{e:?}");
}

#[test]
fn a_model_path_is_a_scene_with_default_lights_and_camera() {
    let scene = Scene::open(Path::new("models/spot.obj")).unwrap();
    assert_eq!(scene.models.len(), 1);
    assert_eq!(scene.models[0].name, "spot");
    assert_eq!(scene.models[0].fix, FixOptions::DEFAULT);
    assert_eq!(scene.lights_or_default().len(), 3);
    let bounds = (Vec3::splat(-1.0), Vec3::ONE);
    let cameras = scene.cameras_or_default(bounds, 1.0);
    assert_eq!(cameras.len(), 1);
    assert_eq!(Scene::find_camera(&cameras, None).unwrap().name, "default");
    let e = Scene::find_camera(&cameras, Some("top")).unwrap_err();
    assert_eq!(e, "no camera named \"top\" (there are: default)");
}

#[test]
fn a_missing_scene_file_names_the_file() {
    let e = Scene::open(Path::new("/nonexistent/scene.toml")).unwrap_err().to_string();
    assert!(e.starts_with("/nonexistent/scene.toml: cannot read"), "{e}");
}
