//! The OBJ pass-through (issue 11): an OBJ fixed and saved as OBJ is its input with only the
//! `vn` lines and the faces' normal references new. Each model is loaded, fixed as `seamlit
//! fix` fixes it (`fix_in_place`, default options) and saved; the output is then compared with
//! the input as text, line by line, by this file's own reader, and loaded again to compare
//! every triangle corner with the fixed model.

mod common;

use std::path::{Path, PathBuf};

use seamlit_io::{Asset, LoadOptions, SaveOptions, SaveReport};
use seamlit_mesh::{FixOptions, Object};

/// A scene written for these tests: CRLF line ends, comments, a UTF-8 name, statements
/// seamlit does not know (`vp`, `cstype`, `bevel`, `l`, `p`, `shadow_obj`), vertex colours,
/// a concave polygon (an L), relative indices, a face of two corners, smoothing groups,
/// authored normals on two objects that meet at a seam, none on a folded third, two
/// materials, and a last line without a line end.
const SCENE: &str = "\
# a scene built by obj_pass_through.rs\r
mtllib scene.mtl\r
shadow_obj shadow.obj\r
cstype bezier\r
o floor_and_ramp\r
v 0 0 0 1 0 0\r
v 2 0 0 0 1 0\r
v 2 1 0 0 0 1\r
v 1 1 0 1 1 0\r
v 1 2 0 0 1 1\r
v 0 2 0 1 0 1\r
v 3 0 0.2 0.5 0.5 0.5\r
v 3 1 0.2 0.25 0.5 0.75\r
vt 0 0\r
vt 1 0\r
vt 1 0.5\r
vt 0.5 0.5\r
vt 0.5 1\r
vt 0 1\r
vp 0.5 0.5\r
vn 0 0 1\r
vn -0.19611613 0 0.9805807\r
g floor\r
usemtl shiny\r
s 1\r
bevel off\r
f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1 6/6/1\r
l 1/1 2/2 3/3\r
p 4\r
f 1/1/1 2/2/1\r
g ramp  # the ramp\u{e9}\r
usemtl matte\r
f  2/2/2\t7/1/2 8/6/2  3/3/2\r
o fold\r
s off\r
v 5 0 0 0 0 0\r
v 6 0 0 0 0 0\r
v 6 1 0 0 0 0\r
v 5 1 0 0 0 0\r
f -4 -3 -2 -1\r
v 6 0 1 0 0 0\r
v 6 1 1 0 0 0\r
f 10 11 14 13\r
# end without a line end";

/// The material library of [`SCENE`]: statements seamlit does not read, an inline comment,
/// a texture with options in a subfolder.
const SCENE_MTL: &str = "\
# materials\r
newmtl shiny\r
Kd 1 0 0 # red\r
Pr 0.25\r
aniso 0.5\r
illum 2\r
map_Kd -o 0.5 0.5 1 tex/checker.png\r
\r
newmtl matte\r
Kd 0.5 0.5 0.5\r
Tf 1 1 1\r
";

/// A PNG of one white pixel.
const PNG: &[u8] = &[
    0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0x1F, 0x15, 0xC4,
    0x89, 0x00, 0x00, 0x00, 0x0D, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9C, 0x63, 0xF8, 0xFF, 0xFF, 0xFF,
    0x7F, 0x00, 0x09, 0xFB, 0x03, 0xFD, 0xE3, 0x55, 0xF2, 0x9C, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
    0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82,
];

/// Writes [`SCENE`], its library and texture into `dir`/in; returns the OBJ's path.
fn write_scene(dir: &Path) -> PathBuf {
    let input = dir.join("in");
    std::fs::create_dir_all(input.join("tex")).unwrap();
    std::fs::write(input.join("scene.obj"), SCENE).unwrap();
    std::fs::write(input.join("scene.mtl"), SCENE_MTL).unwrap();
    std::fs::write(input.join("tex/checker.png"), PNG).unwrap();
    input.join("scene.obj")
}

/// Loads `input`, fixes it as `seamlit fix` does and saves it as `dir`/out/NAME.obj.
fn fix_and_save(input: &Path, dir: &Path) -> (Asset, PathBuf, SaveReport) {
    fix_and_save_with(input, dir, &FixOptions::default())
}

/// [`fix_and_save`] with `options`.
fn fix_and_save_with(
    input: &Path,
    dir: &Path,
    options: &FixOptions,
) -> (Asset, PathBuf, SaveReport) {
    let mut asset = seamlit_io::load(input, &LoadOptions::default()).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, options).unwrap();
    let output = dir.join("out").join(input.file_name().unwrap());
    std::fs::create_dir_all(output.parent().unwrap()).unwrap();
    let report = seamlit_io::save(&asset, &output, &SaveOptions::default()).unwrap();
    (asset, output, report)
}

/// The lines of `text` with their line ends, and the keyword of each.
fn lines(text: &[u8]) -> Vec<(&[u8], &[u8])> {
    text.split_inclusive(|&b| b == b'\n')
        .map(|line| {
            let keyword =
                line.split(|b| b.is_ascii_whitespace()).find(|w| !w.is_empty()).unwrap_or_default();
            (keyword, line)
        })
        .collect()
}

/// Every line that is neither `vn` nor `f`, as written.
fn kept(text: &[u8]) -> Vec<&[u8]> {
    lines(text).into_iter().filter(|(k, _)| !matches!(*k, b"vn" | b"f")).map(|(_, l)| l).collect()
}

/// Each face's corners as written, without their normal reference: `v` and `vt` fields.
fn faces(text: &[u8]) -> Vec<Vec<(String, String)>> {
    lines(text)
        .into_iter()
        .filter(|(k, _)| *k == b"f")
        .map(|(_, line)| {
            String::from_utf8_lossy(line)
                .split_whitespace()
                .skip(1)
                .map(|corner| {
                    let mut fields = corner.split('/');
                    let v = fields.next().unwrap_or_default().to_owned();
                    (v, fields.next().unwrap_or_default().to_owned())
                })
                .collect()
        })
        .collect()
}

/// Per face, per corner, the normal its reference resolves to among the text's `vn` lines
/// (`None` for a corner without one), read with plain string handling.
fn corner_normals(text: &[u8]) -> Vec<Vec<Option<[f32; 3]>>> {
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut out = Vec::new();
    for (keyword, line) in lines(text) {
        let line = String::from_utf8_lossy(line);
        let words: Vec<&str> = line.split_whitespace().skip(1).collect();
        match keyword {
            b"vn" => normals.push([0, 1, 2].map(|i| words[i].parse().unwrap())),
            b"f" => out.push(
                words
                    .iter()
                    .map(|corner| {
                        let vn = corner.split('/').nth(2).filter(|f| !f.is_empty())?;
                        let i: i64 = vn.parse().unwrap();
                        let i = if i < 0 { normals.len() as i64 + i } else { i - 1 };
                        Some(normals[usize::try_from(i).unwrap()])
                    })
                    .collect(),
            ),
            _ => {}
        }
    }
    out
}

/// Per object, per triangle, the first triangle of the face it comes from: a face of `n`
/// corners gives `n - 2` triangles, faces fill the objects in file order.
fn face_starts(text: &[u8], objects: &[Object]) -> Vec<Vec<usize>> {
    let mut faces = faces(text).into_iter().map(|f| f.len()).filter(|&n| n >= 3);
    objects
        .iter()
        .map(|object| {
            let mut starts = Vec::new();
            while starts.len() < object.triangle_count() {
                let first = starts.len();
                starts.extend(std::iter::repeat_n(first, faces.next().unwrap() - 2));
            }
            starts
        })
        .collect()
}

/// The values at each triangle corner of an object: position, uv, colour, normal (bits).
/// With `starts` (see [`face_starts`]), the normal is the one the corner's vertex has in the
/// first triangle of its face that holds it: a polygon corner has one normal in OBJ.
fn corner_values(object: &Object, starts: Option<&[usize]>) -> Vec<[Option<[u32; 4]>; 4]> {
    let bits3 = |v: glam::Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits(), 0];
    let in_face = |t: usize, i: u32| {
        let Some(starts) = starts else { return i };
        let source = object.source_vertex(i);
        (starts[t]..=t)
            .flat_map(|t| object.triangles[t])
            .find(|&j| object.source_vertex(j) == source)
            .unwrap_or(i)
    };
    (0..object.triangle_count())
        .flat_map(|t| (0..3).map(move |k| (t, k)))
        .map(|(t, k)| {
            let v = object.triangles[t][k];
            let i = v as usize;
            let n = in_face(t, v) as usize;
            [
                Some(bits3(object.positions[i])),
                object.uvs.as_ref().map(|uv| [uv[i].x.to_bits(), uv[i].y.to_bits(), 0, 0]),
                object.colors.as_ref().map(|c| c[i].to_array().map(f32::to_bits)),
                object.normals.as_ref().map(|normals| bits3(normals[n])),
            ]
        })
        .collect()
}

/// The whole comparison of an input OBJ with its pass-through output; `fixed` is the input
/// as fixed.
fn check_pass_through(input: &Path, output: &Path, fixed: &Asset) {
    let (before, after) = (std::fs::read(input).unwrap(), std::fs::read(output).unwrap());
    let name = input.display();

    // Every line but `vn` and `f` is the input's, byte for byte and in order.
    assert_eq!(kept(&before), kept(&after), "{name}: the lines seamlit does not own");

    // Faces keep their corners and their `v` / `vt` references as written.
    assert_eq!(faces(&before), faces(&after), "{name}: faces");

    // Loading the output gives the fixed model, corner by corner: positions, uvs and colours
    // as loaded, normals as fixed.
    let reloaded = seamlit_io::load(output, &LoadOptions::default()).unwrap();
    assert_eq!(reloaded.model.objects.len(), fixed.model.objects.len(), "{name}: objects");
    let starts = face_starts(&before, &fixed.model.objects);
    for ((got, want), starts) in
        reloaded.model.objects.iter().zip(&fixed.model.objects).zip(&starts)
    {
        assert_eq!(got.name, want.name);
        assert!(want.normals.is_some(), "{name}: {}: fix gave no normals", want.name);
        let (got, want) = (corner_values(got, None), corner_values(want, Some(starts)));
        assert_eq!(got.len(), want.len(), "{name}: corners");
        for (c, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "{name}: corner {c} (position, uv, colour, normal bits)");
        }
    }
}

#[test]
fn a_built_scene_keeps_everything_seamlit_does_not_own() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_scene(dir.path());
    // The floor and the ramp carry their faces' normals: an authored hard edge that the
    // default keeps (issue 31); `smooth-shared` repairs it, so that new normals are written.
    let shared = FixOptions::default().with_normals(seamlit_mesh::NormalPolicy::SmoothShared);
    let (fixed, output, report) = fix_and_save_with(&input, dir.path(), &shared);
    check_pass_through(&input, &output, &fixed);

    let after = std::fs::read(&output).unwrap();
    // The fix split the fold's shared edge (`s off`): split copies exist, and the output
    // still lines up.
    assert!(!fixed.model.objects[2].split_from.is_empty(), "no vertex was split");
    // The seam between floor and ramp got new normals: the ramp's corner at (2, 0, 0) no
    // longer has its authored normal.
    let ramp = corner_normals(&after)[2].clone();
    assert_ne!(ramp[0], Some([-0.196_116_13, 0.0, 0.980_580_7]), "the seam was not repaired");
    // Away from the seam the floor's authored normal is kept, bit for bit.
    assert_eq!(corner_normals(&after)[0][5], Some([0.0, 0.0, 1.0]));
    // Every face of three corners or more has a normal at every corner; the face of two
    // corners has none (the input's `vn` are gone).
    for (f, corners) in corner_normals(&after).iter().enumerate() {
        let expected = corners.len() >= 3;
        assert!(corners.iter().all(|n| n.is_some() == expected), "face {f}: {corners:?}");
    }
    // New lines end as the file's do.
    assert!(
        lines(&after).iter().filter(|(k, _)| *k == b"vn").all(|(_, l)| l.ends_with(b"\r\n")),
        "a vn line without CRLF"
    );

    // The library and its texture are copied as written.
    for side in ["scene.mtl", "tex/checker.png"] {
        let copied = std::fs::read(dir.path().join("out").join(side));
        assert_eq!(
            copied.ok(),
            Some(std::fs::read(dir.path().join("in").join(side)).unwrap()),
            "{side}"
        );
    }
    // OBJ cannot hold the tangents fix computed (the scene has UVs): the report says so.
    assert!(
        report.warnings.iter().any(|w| w.contains("OBJ has no tangents")),
        "{:?}",
        report.warnings
    );
}

#[test]
fn the_models_in_the_repository_pass_through() {
    for relative in [
        "groups.obj",
        "cornell_box/cornell_box.obj",
        "spot/spot_triangulated.obj",
        "spot/spot_quadrangulated.obj",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let input = common::model(relative);
        let (fixed, output, report) = fix_and_save(&input, dir.path());
        check_pass_through(&input, &output, &fixed);
        assert!(
            !report.warnings.iter().any(|w| w.contains("generic OBJ writer")),
            "{relative}: {:?}",
            report.warnings
        );
        if relative == "groups.obj" {
            // Its normals are all kept (`auto`, no seam needs a repair): every corner has its
            // input value, bit for bit, and no value is written twice.
            let (before, after) = (std::fs::read(&input).unwrap(), std::fs::read(&output).unwrap());
            assert_eq!(corner_normals(&before), corner_normals(&after), "{relative}");
            let count = |text: &[u8]| lines(text).iter().filter(|(k, _)| *k == b"vn").count();
            assert!(count(&after) <= count(&before), "{} vn > {}", count(&after), count(&before));
        }
        if relative.starts_with("cornell_box") {
            // Its library copied byte for byte; the second `mtllib` names a missing file,
            // which is a warning, not an error.
            assert_eq!(
                std::fs::read(dir.path().join("out/cornell_box.mtl")).ok(),
                Some(std::fs::read(common::model("cornell_box/cornell_box.mtl")).unwrap())
            );
            assert!(
                report
                    .warnings
                    .iter()
                    .any(|w| w.contains("cornell_box2.mtl") && w.contains("missing")),
                "{:?}",
                report.warnings
            );
        }
    }
}

#[test]
fn a_model_that_no_longer_lines_up_goes_through_the_generic_writer() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_scene(dir.path());
    let mut asset = seamlit_io::load(&input, &LoadOptions::default()).unwrap();
    // As seamlit-scene's `merge` does: another object appended.
    let extra = asset.model.objects[0].clone();
    asset.model.objects.push(extra);
    let output = dir.path().join("merged.obj");
    let report = seamlit_io::save(&asset, &output, &SaveOptions::default()).unwrap();
    assert!(
        report.warnings.iter().any(|w| w.contains("generic OBJ writer") && w.contains("4 objects")),
        "{:?}",
        report.warnings
    );
    assert!(std::fs::read_to_string(&output).unwrap().starts_with("# written by seamlit"));

    // Nor does an object with a transform (OBJ positions are written as the input's).
    let mut asset = seamlit_io::load(&input, &LoadOptions::default()).unwrap();
    asset.model.objects[1].transform = Some(glam::Mat4::from_translation(glam::Vec3::X));
    let report = seamlit_io::save(&asset, &output, &SaveOptions::default()).unwrap();
    assert!(
        report.warnings.iter().any(|w| w.contains("\"ramp  # the ramp\u{e9}\" has a transform")),
        "{:?}",
        report.warnings
    );

    // Triangles changed in place (same counts) do not line up either.
    let mut asset = seamlit_io::load(&input, &LoadOptions::default()).unwrap();
    asset.model.objects[0].triangles[0].swap(1, 2);
    let report = seamlit_io::save(&asset, &output, &SaveOptions::default()).unwrap();
    assert!(
        report.warnings.iter().any(|w| w.contains("does not have the triangles")),
        "{:?}",
        report.warnings
    );
}

#[test]
fn a_missing_library_is_a_warning_and_the_output_still_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_scene(dir.path());
    std::fs::remove_file(dir.path().join("in/scene.mtl")).unwrap();
    let (_, output, report) = fix_and_save(&input, dir.path());
    assert!(
        report.warnings.iter().any(|w| w.contains("scene.mtl") && w.contains("missing")),
        "{:?}",
        report.warnings
    );
    assert!(std::fs::read_to_string(output).unwrap().contains("mtllib scene.mtl\r\n"));
}

#[test]
fn a_utf8_byte_order_mark_is_kept_and_utf16_is_written_as_utf8() {
    let dir = tempfile::tempdir().unwrap();
    let input = write_scene(dir.path());
    let (_, plain, _) = fix_and_save(&input, dir.path());
    let plain = std::fs::read(plain).unwrap();

    let bom = dir.path().join("in/bom.obj");
    std::fs::write(&bom, [b"\xEF\xBB\xBF", SCENE.as_bytes()].concat()).unwrap();
    let (_, output, _) = fix_and_save(&bom, dir.path());
    assert_eq!(std::fs::read(output).unwrap(), [b"\xEF\xBB\xBF", &plain[..]].concat());

    let wide = dir.path().join("in/wide.obj");
    let utf16: Vec<u8> =
        [0xFF, 0xFE].into_iter().chain(SCENE.encode_utf16().flat_map(u16::to_le_bytes)).collect();
    std::fs::write(&wide, utf16).unwrap();
    let (_, output, _) = fix_and_save(&wide, dir.path());
    assert_eq!(String::from_utf8(std::fs::read(output).unwrap()).unwrap().as_bytes(), plain);
}

#[test]
fn objects_split_and_merged_by_usemtl_and_named_again_line_up() {
    // Faces before any `o`; `usemtl` parts that merge back (no library: every name resolves
    // to no material); a `g` without faces; a name used twice; `v` lines between faces.
    // Not planar, so that every vertex gets a normal of its own.
    let text = "v 0 0 0\nv 1 0 0.3\nv 1 1 -0.2\nv 0 1 0.4\nf 1 2 3\n\
                o a\nusemtl m1\nf 1 3 4\nusemtl m2\nf -3 -2 -1\ng empty\n\
                o b\nv 2 0 0.1\nv 2 1 0.5\nf 2 5 6 3\n\
                o a\nv 0 2 0.2\nf 4 3 7\nusemtl m1\nf 3 6 7\n";
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("parts.obj");
    std::fs::write(&input, text).unwrap();
    let (fixed, output, report) = fix_and_save(&input, dir.path());
    let names: Vec<&str> = fixed.model.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["unnamed_object", "a", "b", "a"]);
    assert!(!report.warnings.iter().any(|w| w.contains("generic OBJ writer")), "{report:?}");
    check_pass_through(&input, &output, &fixed);
}
