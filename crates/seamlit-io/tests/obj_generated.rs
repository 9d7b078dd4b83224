//! The OBJ parser against tobj on generated files: random mixes of `v`, `vt`, `vn`, faces of
//! every corner form (`v`, `v/vt`, `v//vn`, `v/vt/vn`) with positive and negative indices,
//! points and lines (`p`, `l` of two points, faces of one or two corners), `o`, `g` and
//! `usemtl`, numbers written in many ways, CRLF line ends and
//! tabs; some files several megabytes long, so that the parser's blocks (about 1 MB each, cut
//! at line ends) split objects and faces refer back across blocks. Every file must give
//! exactly what tobj gives: objects, names, vertex arrays (bit for bit) and triangles, but for
//! polygons that are not convex, which tobj fans and seamlit-io ear-clips; and the same with
//! one thread as with several.

use std::fmt::Write as _;
use std::path::Path;

use seamlit_io::LoadOptions;

/// xorshift64*: a small deterministic generator, so that failures reproduce.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.below(100) < percent
    }
    fn pick<'a>(&mut self, options: &[&'a str]) -> &'a str {
        options[usize::try_from(self.below(options.len() as u64)).unwrap()]
    }
}

/// A number written the way exporters do: shortest round-trip, fixed digits, exponents,
/// integers, signs, leading or trailing points, more digits than an f32 holds.
#[expect(clippy::cast_possible_truncation, reason = "the f32 roundings are the point")]
fn number(r: &mut Random) -> String {
    let x = (r.below(2_000_001) as f64 - 1_000_000.0) / 100_000.0;
    match r.below(10) {
        0 => format!("{}", x as f32),
        1 => format!("{x:.6}"),
        2 => format!("{x:.9}"),
        3 => format!("{:e}", x * 1e-7),
        4 => format!("{}", r.below(100)),
        5 => format!("{x:.17}"),
        6 => r
            .pick(&["-0", "+1.5", ".5", "5.", "-.25", "1e-3", "2.5E2", "1.0000000596046448"])
            .to_owned(),
        7 => format!("{:.3}", x * 1e6),
        _ => format!("{}", (x / 3.0) as f32),
    }
}

/// One face corner of the given form, with indices in range (negative ones counting back).
fn corner(r: &mut Random, form: usize, counts: [usize; 3]) -> String {
    let mut index = |count: usize| -> String {
        if r.chance(30) {
            format!("-{}", 1 + r.below(count.min(5000) as u64))
        } else {
            format!("{}", 1 + r.below(count as u64))
        }
    };
    match form {
        0 => index(counts[0]),
        1 => format!("{}/{}", index(counts[0]), index(counts[1])),
        2 => format!("{}//{}", index(counts[0]), index(counts[2])),
        _ => format!("{}/{}/{}", index(counts[0]), index(counts[1]), index(counts[2])),
    }
}

fn generate(seed: u64, lines: usize) -> String {
    let mut r = Random(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let newline = if r.chance(30) { "\r\n" } else { "\n" };
    let mut text = String::new();
    let mut counts = [0usize; 3];
    // The corner form of the current object: every face of an object has the same form (the
    // loader drops `vt` / `vn` of an object where only some faces have them, tobj does not).
    let mut form = 3;
    for _ in 0..lines {
        let roll = r.below(100);
        let blank = r.pick(&[" ", " ", "\t", "  "]);
        if roll < 25 || counts[0] == 0 {
            let [x, y, z] = [number(&mut r), number(&mut r), number(&mut r)];
            write!(text, "v{blank}{x} {y} {z}").unwrap();
            counts[0] += 1;
        } else if roll < 35 || counts[1] == 0 {
            let [u, v] = [number(&mut r), number(&mut r)];
            write!(text, "vt {u}{blank}{v}").unwrap();
            counts[1] += 1;
        } else if roll < 45 || counts[2] == 0 {
            let [x, y, z] = [number(&mut r), number(&mut r), number(&mut r)];
            write!(text, "vn {x} {y} {z}").unwrap();
            counts[2] += 1;
        } else if roll < 90 {
            let corners = r.pick(&["3", "3", "3", "4", "4", "5", "2", "1", "8"]);
            let corners: usize = corners.parse().unwrap();
            let words: Vec<String> = (0..corners).map(|_| corner(&mut r, form, counts)).collect();
            // `p` statements are ignored by both; `l` polylines of three or more points
            // are polygons to tobj, but lines (ignored) to seamlit-io: only two points here.
            let keyword = if r.chance(3) { r.pick(&["l", "p"]) } else { "f" };
            let words = if keyword == "l" { &words[..words.len().min(2)] } else { &words[..] };
            write!(text, "{keyword} {}", words.join(blank)).unwrap();
        } else if roll < 95 {
            let keyword = r.pick(&["o", "g"]);
            let name = r.pick(&["", "part", "part two", "Leg_1", "leg_2", "café"]);
            write!(text, "{keyword} {name}").unwrap();
            form = usize::try_from(r.below(4)).unwrap();
        } else if roll < 98 {
            write!(text, "usemtl {}", r.pick(&["red", "green", "blue"])).unwrap();
        } else {
            text.push_str(r.pick(&["# a comment", "", "s 1", "s off", "   "]));
        }
        text.push_str(newline);
    }
    text
}

/// tobj's models of `path` that have faces, fan-triangulated or as polygons.
fn tobj_models(path: &Path, triangulate: bool) -> Vec<tobj::Model> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _) = tobj::load_obj(path, &options).unwrap();
    models.into_iter().filter(|m| !m.mesh.indices.is_empty()).collect()
}

/// Whether `ours` triangulates the faces of tobj's `polygons` as tobj's `fan` does, except
/// that a polygon may have another triangulation of its corners (ear clipping, where it is
/// not convex): as many triangles, on the polygon's corners only, using every one.
fn same_faces(ours: &[[u32; 3]], fan: &[u32], polygons: &tobj::Mesh) -> bool {
    let arities: Vec<usize> = if polygons.face_arities.is_empty() {
        vec![3; polygons.indices.len() / 3]
    } else {
        polygons.face_arities.iter().map(|&a| a as usize).collect()
    };
    if ours.len() * 3 != fan.len() {
        return false;
    }
    let (mut triangle, mut corner) = (0, 0);
    for arity in arities {
        let n = arity - 2;
        let mine = &ours[triangle..triangle + n];
        let face = &polygons.indices[corner..corner + arity];
        let same_fan = mine.as_flattened() == &fan[triangle * 3..(triangle + n) * 3];
        let mut used: Vec<u32> = mine.as_flattened().to_vec();
        let mut corners = face.to_vec();
        for list in [&mut used, &mut corners] {
            list.sort_unstable();
            list.dedup();
        }
        if !(same_fan || (arity > 3 && used == corners)) {
            return false;
        }
        (triangle, corner) = (triangle + n, corner + arity);
    }
    triangle == ours.len()
}

/// Loads `path` with tobj and with seamlit-io and compares everything tobj reports.
fn agree(path: &Path, label: &str) {
    let models = tobj_models(path, true);
    let polygons = tobj_models(path, false);
    assert_eq!(models.len(), polygons.len(), "{label}");
    let asset = match seamlit_io::load(path, &LoadOptions::default()) {
        Err(seamlit_io::IoError::NoTriangles { .. }) if models.is_empty() => return,
        other => other.unwrap(),
    };
    assert_eq!(asset.model.objects.len(), models.len(), "{label}");
    for ((ours, theirs), polygons) in asset.model.objects.iter().zip(&models).zip(&polygons) {
        assert_eq!(ours.name, theirs.name, "{label}");
        let bits = |v: &mut dyn Iterator<Item = f32>| v.map(f32::to_bits).collect::<Vec<_>>();
        let positions = bits(&mut ours.positions.iter().flat_map(|p| p.to_array()));
        assert_eq!(positions, bits(&mut theirs.mesh.positions.iter().copied()), "{label}");
        let uvs = bits(&mut ours.uvs.iter().flatten().flat_map(|t| t.to_array()));
        assert_eq!(uvs, bits(&mut theirs.mesh.texcoords.iter().copied()), "{label}");
        let normals = bits(&mut ours.normals.iter().flatten().flat_map(|n| n.to_array()));
        assert_eq!(normals, bits(&mut theirs.mesh.normals.iter().copied()), "{label}");
        assert!(
            same_faces(&ours.triangles, &theirs.mesh.indices, &polygons.mesh),
            "{label} {}: {:?} vs {:?}",
            ours.name,
            ours.triangles,
            theirs.mesh.indices
        );
    }
}

#[test]
fn small_generated_files_agree_with_tobj() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 0..150 {
        let path = dir.path().join(format!("small{seed}.obj"));
        std::fs::write(&path, generate(seed, 40)).unwrap();
        agree(&path, &format!("seed {seed}"));
    }
}

#[test]
fn generated_files_of_several_blocks_agree_with_tobj() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 1000..1003 {
        let path = dir.path().join(format!("large{seed}.obj"));
        let text = generate(seed, 150_000);
        assert!(text.len() > 3 << 20, "{} bytes", text.len());
        std::fs::write(&path, text).unwrap();
        agree(&path, &format!("seed {seed}"));
    }
}

#[test]
fn one_thread_and_several_give_the_same_objects() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("threads.obj");
    std::fs::write(&path, generate(77, 150_000)).unwrap();
    let load = || seamlit_io::load(&path, &LoadOptions::default()).unwrap().model;
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(load);
    let four = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap().install(load);
    assert_eq!(one, four);
}

/// Pads `text` with a comment line so that it is exactly `size` bytes long.
fn pad_to(mut text: String, size: usize) -> String {
    let fill = size - text.len() - 2;
    text.push('#');
    text.extend(std::iter::repeat_n('x', fill));
    text.push('\n');
    assert_eq!(text.len(), size);
    text
}

/// The parser reads about 1 MiB at a time, cut after the last line end: lines longer than
/// a block, a block that ends exactly at a line end, and a last line without one.
#[test]
fn long_lines_and_block_edges_agree_with_tobj() {
    const BLOCK: usize = 1 << 20;
    let dir = tempfile::tempdir().unwrap();
    let mut r = Random(5);
    let mut positions = String::new();
    for _ in 0..200_000 {
        let [x, y, z] = [number(&mut r), number(&mut r), number(&mut r)];
        writeln!(positions, "v {x} {y} {z}").unwrap();
    }
    let fan: Vec<String> = (1..=200_000).map(|i| i.to_string()).collect();
    let files = [
        // A 3 MiB comment before the geometry.
        format!("# {}\no first\n{positions}f 1 2 3\nf -1 -2 -3 -4\n", "x".repeat(3 * BLOCK)),
        // One face of 200,000 corners (a line of 1.3 MB), then more faces.
        format!("o fan\n{positions}f {}\no after\nf -3 -2 -1\n", fan.join(" ")),
        // A block ends exactly at a line end; the next one refers back across it; the file
        // ends without a line end.
        pad_to("v 0 0 0\nv 1 0 0\nv 0 1 0\no a\nf 1 2 3\n".to_owned(), BLOCK)
            + "v 0 0 1\no b\nf -1 -2 -3\nf 1 2 -1",
        // A block one byte short of that.
        pad_to("v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_owned(), BLOCK - 1) + "f 1 2 3\nf -3 -2 -1\n",
    ];
    for (k, text) in files.iter().enumerate() {
        let path = dir.path().join(format!("edge{k}.obj"));
        std::fs::write(&path, text).unwrap();
        agree(&path, &format!("file {k}"));
    }
    // Counted by hand: a fan of n corners is n - 2 triangles.
    let counts = |k: usize| -> Vec<(String, usize)> {
        let path = dir.path().join(format!("edge{k}.obj"));
        let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
        asset.model.objects.into_iter().map(|o| (o.name, o.triangles.len())).collect()
    };
    assert_eq!(counts(0), [("first".to_owned(), 3)]);
    assert_eq!(counts(1), [("fan".to_owned(), 199_998), ("after".to_owned(), 1)]);
    assert_eq!(counts(2), [("a".to_owned(), 1), ("b".to_owned(), 2)]);
    assert_eq!(counts(3), [("unnamed_object".to_owned(), 2)]);
}
