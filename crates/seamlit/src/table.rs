//! The seam report as a readable table: one row per measure, one column per model state.

use std::fmt::Write as _;

use seamlit_mesh::{Changes, SeamReport};

pub(crate) use seamlit_io::job::{changes_line, count};

/// Formats reports side by side; `columns` are `(heading, report)`.
#[must_use]
pub(crate) fn report_table(columns: &[(&str, &SeamReport)]) -> String {
    type Cell = fn(&SeamReport) -> String;
    let rows: [(&str, Cell); 21] = [
        ("objects", |r| r.objects.to_string()),
        ("triangles", |r| r.triangles.to_string()),
        ("vertices", |r| r.vertices.to_string()),
        ("welded positions", |r| r.welded_positions.to_string()),
        ("weld tolerance", |r| format!("{:.1e}", r.weld_tolerance)),
        ("positions shared by 2+ objects", |r| r.shared_positions.to_string()),
        ("near-miss positions", |r| r.near_miss_positions.to_string()),
        ("degenerate triangles", |r| r.degenerate_triangles.to_string()),
        ("degenerate UV triangles", |r| r.degenerate_uv_triangles.to_string()),
        ("mirrored triangles", |r| r.mirrored_triangles.to_string()),
        ("cross-object edges", |r| r.cross_object.edges.to_string()),
        ("  of which hard (> crease)", |r| r.cross_object.hard_edges.to_string()),
        ("normal angle across seams, max", |r| fmt_deg(r.cross_object.max_normal_angle_deg)),
        ("normal angle across seams, mean", |r| fmt_deg(r.cross_object.mean_normal_angle_deg)),
        ("corner pairs with normals > 1° apart", |r| {
            format!("{} of {}", r.cross_object.normal_breaks, r.cross_object.corner_pairs)
        }),
        ("tangent angle across seams, max", |r| fmt_deg(r.cross_object.max_tangent_angle_deg)),
        ("tangent angle across seams, mean", |r| fmt_deg(r.cross_object.mean_tangent_angle_deg)),
        ("max |N·T| (0 = orthogonal)", |r| fmt_small(r.max_abs_dot_nt)),
        ("max normal length error", |r| fmt_small(r.max_normal_length_error)),
        ("tangents with bad handedness", |r| r.bad_handedness.to_string()),
        ("shared positions whose skins differ", |r| r.skin_seams.positions.to_string()),
    ];
    let label_width = rows.iter().map(|(l, _)| l.chars().count()).max().unwrap_or(0);
    let cells: Vec<Vec<String>> =
        rows.iter().map(|(_, f)| columns.iter().map(|(_, r)| f(r)).collect()).collect();
    let widths: Vec<usize> = (0..columns.len())
        .map(|c| {
            cells
                .iter()
                .map(|row| row[c].chars().count())
                .chain([columns[c].0.chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    let _ = write!(out, "{:label_width$}", "");
    for (c, (heading, _)) in columns.iter().enumerate() {
        let _ = write!(out, "  {heading:>w$}", w = widths[c]);
    }
    out.push('\n');
    for ((label, _), row) in rows.iter().zip(&cells) {
        let _ = write!(out, "{label:label_width$}");
        for (c, cell) in row.iter().enumerate() {
            let _ = write!(out, "  {cell:>w$}", w = widths[c]);
        }
        out.push('\n');
    }
    out
}

/// What a fix changed, one row per object.
#[must_use]
pub(crate) fn changes_table(changes: &Changes) -> String {
    let mut out = String::new();
    let width =
        changes.objects.iter().map(|o| o.name.chars().count()).chain([6]).max().unwrap_or(6);
    let _ = writeln!(
        out,
        "{:width$}  {:>8}  {:>8}  {:>8}  {:>15}  {:>5}",
        "object", "normals", "tangents", "vertices", "normals changed", "split"
    );
    for o in &changes.objects {
        let source = |kept: bool| if kept { "kept" } else { "computed" };
        let _ = writeln!(
            out,
            "{:width$}  {:>8}  {:>8}  {:>8}  {:>15}  {:>5}",
            o.name,
            source(o.kept_normals),
            source(o.kept_tangents),
            o.vertices,
            o.normals_changed,
            o.vertices_split
        );
    }
    out
}

fn fmt_deg(v: Option<f32>) -> String {
    v.map_or_else(|| "-".to_string(), |d| format!("{d:.2}°"))
}

fn fmt_small(v: Option<f32>) -> String {
    v.map_or_else(|| "-".to_string(), |d| format!("{d:.1e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_line_up_and_missing_values_show_a_dash() {
        let mut a = SeamReport { objects: 32, triangles: 9216, ..SeamReport::default() };
        a.cross_object.max_normal_angle_deg = Some(41.234);
        let b = SeamReport { objects: 32, ..SeamReport::default() };
        let t = report_table(&[("object", &a), ("model", &b)]);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[0].ends_with("object   model"), "{:?}", lines[0]);
        let max = lines.iter().find(|l| l.starts_with("normal angle across seams, max")).unwrap();
        let cells: Vec<&str> = max.split_whitespace().collect();
        assert_eq!(cells[cells.len() - 2..], ["41.23°", "-"], "{max:?}");
        let widths: Vec<usize> = lines.iter().map(|l| l.chars().count()).collect();
        assert!(widths.iter().all(|w| *w == widths[0]), "{widths:?}");
    }
}
