//! `render` and `compare`: scenes, cameras, debug views, environments.

use super::*;

// --- render and compare ------------------------------------------------------------------

#[test]
fn render_draws_the_example_scene_through_a_named_camera_and_times_frames() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("side.png");
    let o = seamlit(&[
        "render",
        &example("teapot.toml"),
        "-o",
        &out.display().to_string(),
        "--size",
        "160x120",
        "--camera",
        "side",
        "--tessellation",
        "4",
        "--frames",
        "3",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (160, 120));
    let f = foreground_fraction(&img, 0);
    assert!(f > 0.1 && f < 0.9, "the teapot covers {f} of the picture");
    assert!(stdout(&o).contains("3 frames at 160x120"), "{}", stdout(&o));
}

#[test]
fn render_debug_views_and_a_bare_model_with_the_default_camera() {
    let dir = tempfile::tempdir().unwrap();
    let path = models().join("spot/spot_triangulated.obj").display().to_string();
    for view in ["normals", "objects", "uv"] {
        let out = dir.path().join(format!("{view}.png"));
        let o = seamlit(&[
            "render",
            &path,
            "-o",
            &out.display().to_string(),
            "--size",
            "96x96",
            "--view",
            view,
        ]);
        assert_eq!(o.status.code(), Some(0), "{view}: {}", String::from_utf8_lossy(&o.stderr));
        let f = foreground_fraction(&image::open(&out).unwrap().to_rgba8(), 0);
        assert!(f > 0.1, "{view}: the default camera frames the cow ({f})");
    }
}

#[test]
fn render_a_scene_of_two_placed_models_with_their_own_options() {
    // examples/spot.toml: the cow twice, the second scaled, turned, moved, processed per
    // object with MikkTSpace tangents; no lights (the default rig). Seen from above, both
    // cows show: ink on the left and on the right half of the picture.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("top.png");
    let o = seamlit(&[
        "render",
        &example("spot.toml"),
        "-o",
        &out.display().to_string(),
        "--size",
        "160x120",
        "--camera",
        "top",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("camera \"top\""), "{}", stdout(&o));
    let img = image::open(&out).unwrap().to_rgba8();
    let left = image::imageops::crop_imm(&img, 0, 0, 80, 120).to_image();
    let right = image::imageops::crop_imm(&img, 80, 0, 80, 120).to_image();
    let (l, r) = (foreground_fraction(&left, 0), foreground_fraction(&right, 0));
    assert!(l > 0.05 && r > 0.02, "left {l}, right {r}");
}

#[test]
fn render_refuses_bad_scenes_cameras_and_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png").display().to_string();
    let o = seamlit(&["render", &example("teapot.toml"), "-o", &out, "--camera", "top"]);
    assert_bad_input(&o, &["teapot.toml", "no camera named \"top\"", "front, side"]);
    let scene = write(
        dir.path(),
        "bad.toml",
        &format!(
            "[[model]]\npath = {:?}\n\n[[light]]\ntype = \"point\"\nposition = [0, 1, 0]\ncolour = [1, 0, 0]\n",
            teapot()
        ),
    );
    assert_bad_input(&seamlit(&["render", &scene, "-o", &out]), &["bad.toml", "line 7", "colour"]);
    let missing_model = write(dir.path(), "missing.toml", "[[model]]\npath = \"nope.obj\"\n");
    assert_bad_input(&seamlit(&["render", &missing_model, "-o", &out]), &["nope.obj"]);
    assert_bad_input(
        &seamlit(&["render", &teapot(), "-o", "picture.jpg"]),
        &["picture.jpg", ".png"],
    );
    assert_eq!(listing(dir.path()), ["bad.toml", "missing.toml"]);
}

#[test]
fn compare_puts_the_three_modes_side_by_side_with_labels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid.png");
    let o = seamlit(&[
        "compare",
        &teapot(),
        "-o",
        &out.display().to_string(),
        "--size",
        "120x90",
        "--tessellation",
        "4",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    // Two rows of three 120 px panels with 4 px gaps, each under a 44 px label band: the modes,
    // then the window where object and model differ most, enlarged 5 times.
    assert_eq!(img.dimensions(), (3 * 120 + 2 * 4, 2 * (90 + 44) + 4));
    // The label bands have light text in them above each panel.
    for (panel, band) in (0..3).flat_map(|p| [(p, 0), (p, 90 + 44 + 4)]) {
        let x0 = panel * 124;
        let ink = (x0..x0 + 120)
            .flat_map(|x| (band..band + 44).map(move |y| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0[0] > 150)
            .count();
        assert!(ink > 20, "panel {panel} has no label at row {band}");
    }
    // The window is framed in yellow in each panel; each inset is that window, every pixel a
    // 5 x 5 block of the panel's pixel (nothing smoothed); object's and model's insets differ.
    let framed: Vec<(u32, u32)> = (0..120)
        .flat_map(|x| (44..44 + 90).map(move |y| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x + 124, y).0 == [255, 210, 60, 255])
        .collect();
    // The frame runs from window - 2 to window + size + 1 (span size + 3), clipped to the panel:
    // where it is clipped on the low side, count from the high side.
    let (lo, hi) = framed.iter().fold(((u32::MAX, u32::MAX), (0, 0)), |(lo, hi), &(x, y)| {
        ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)))
    });
    let start = |lo: u32, hi: u32, size: u32| if lo == 0 { hi - size - 1 } else { lo + 2 };
    let (wx, wy) = (start(lo.0, hi.0, 24), start(lo.1 - 44, hi.1 - 44, 18));
    let inset_top = 2 * 44 + 90 + 4;
    let mut differ = 0;
    for panel in 0..3 {
        for y in 0..90 {
            for x in 0..120 {
                let zoomed = img.get_pixel(panel * 124 + x, inset_top + y);
                let source = img.get_pixel(panel * 124 + wx + x / 5, 44 + wy + y / 5);
                assert_eq!(zoomed, source, "panel {panel} inset pixel {x},{y}");
                if panel == 1 && zoomed != img.get_pixel(2 * 124 + x, inset_top + y) {
                    differ += 1;
                }
            }
        }
    }
    assert!(differ > 0, "object and model look the same in the inset");
}

/// A model of one object has no seam: object and model agree, and no inset row is drawn.
#[test]
fn compare_draws_no_inset_where_object_and_model_agree() {
    let dir = tempfile::tempdir().unwrap();
    let one = write(
        dir.path(),
        "one.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0.3\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
    );
    let out = dir.path().join("grid.png");
    let o = seamlit(&["compare", &one, "-o", &out.display().to_string(), "--size", "120x90"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(image::open(&out).unwrap().to_rgba8().dimensions(), (3 * 120 + 2 * 4, 90 + 44));
}

/// A bare model is framed tightly and centred, as glTF viewers frame one: Spot's silhouette
/// spans most of the picture one way and sits in its middle.
#[test]
fn a_bare_model_fills_the_frame_and_sits_in_its_middle() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("spot.png");
    let spot = models().join("spot/spot_triangulated.obj").display().to_string();
    let o = seamlit(&["render", &spot, "-o", &out.display().to_string(), "--size", "200x150"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    let bg = img.get_pixel(0, 0).0;
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0, 0));
    for (x, y, p) in img.enumerate_pixels() {
        let d: i32 = (0..3).map(|k| (i32::from(p.0[k]) - i32::from(bg[k])).abs()).sum();
        if d > 30 {
            (lo, hi) = ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)));
        }
    }
    let (w, h) = (f64::from(hi.0 - lo.0 + 1) / 200.0, f64::from(hi.1 - lo.1 + 1) / 150.0);
    assert!(w.max(h) > 0.7, "the model spans only {w:.2} x {h:.2} of the picture");
    let centre = (f64::from(lo.0 + hi.0) / 400.0, f64::from(lo.1 + hi.1) / 300.0);
    assert!((centre.0 - 0.5).abs() < 0.1 && (centre.1 - 0.5).abs() < 0.1, "centre {centre:?}");
}

/// `--camera side` on a bare model (which has only the framing camera) names the cameras there
/// are, in one line, exit status 2.
#[test]
fn an_unknown_camera_on_a_bare_model_lists_the_cameras_there_are() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png").display().to_string();
    let spot = models().join("spot/spot_triangulated.obj").display().to_string();
    let o = seamlit(&["render", &spot, "-o", &out, "--camera", "side"]);
    assert_bad_input(&o, &["spot_triangulated.obj", "\"side\"", "there are: default"]);
    assert!(!Path::new(&out).exists());
}

#[test]
fn render_and_compare_refuse_a_missing_or_malformed_environment_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let model = models().join("NormalTangentTest.glb").display().to_string();
    let bad = write(dir.path(), "bad.hdr", "#?RADIANCE\nFORMAT=nonsense\n");
    let missing = dir.path().join("missing.hdr").display().to_string();
    for command in ["render", "compare"] {
        let png = dir.path().join("out.png").display().to_string();
        for (hdr, name) in [(&bad, "bad.hdr"), (&missing, "missing.hdr")] {
            let o =
                seamlit(&[command, &model, "-o", &png, "--size", "32x24", "--environment", hdr]);
            assert_bad_input(&o, &[name, "environment"]);
        }
    }
    assert_eq!(listing(dir.path()), ["bad.hdr"]);
    // Every flag of the look is read, and a value out of range is refused by name.
    let png = dir.path().join("ok.png").display().to_string();
    let o = seamlit(&[
        "render",
        &model,
        "-o",
        &png,
        "--size",
        "32x24",
        "--environment",
        "builtin",
        "--environment-intensity",
        "0.5",
        "--environment-rotation",
        "-90",
        "--background",
        "1,1,1",
        "--tone-mapping",
        "aces",
        "--exposure",
        "1.5",
        "--ambient",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let image = image::open(&png).unwrap().to_rgba8();
    assert_eq!(image.get_pixel(0, 0).0, [255, 255, 255, 255], "the background is white");
    let o = seamlit(&["render", &model, "-o", &png, "--background", "1,2,3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("1,2,3"));
}
