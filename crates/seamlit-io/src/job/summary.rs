//! The text `seamlit fix` prints for a model: one line of what was written and the seams
//! after, one of what the fix changed, then lines for the skins, the seams in motion and the
//! morph targets where there are any.

use std::path::Path;

use seamlit_asset::motion::SeamMotion;
use seamlit_mesh::{Changes, FixOptions, NormalPolicy, SharedNormals, SkinSeams, TangentMethod};

use super::Fixed;

/// `n` and the noun, singular for one: `count(1, "object")` is "1 object", `count(2,
/// "object")` "2 objects".
#[must_use]
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 { format!("1 {noun}") } else { format!("{n} {noun}s") }
}

/// [`Fixed::summary`].
pub(super) fn text(fixed: &Fixed, output: &Path) -> String {
    let report = &fixed.report;
    // The report measures every smooth edge between objects; where `auto` kept authored hard
    // edges or custom normals there, the figure includes them: say so.
    let kept = fixed.changes.shared.hard_edges + fixed.changes.shared.custom > 0;
    let seams = report.cross_object.max_normal_angle_deg.map_or_else(String::new, |a| {
        if kept {
            format!(", normals across edges between objects within {a:.2}° (kept ones included)")
        } else {
            format!(", normals across seams within {a:.2}°")
        }
    });
    let skin_seams = skin_seams_line(&report.skin_seams);
    let matched =
        fixed.matched.as_ref().filter(|m| m.positions > 0).map_or_else(String::new, |m| {
            format!(
                "\n  skins: gave the copies at {} the same joints and weights ({} vertices)",
                count(m.positions, "shared position"),
                m.vertices
            )
        });
    let motion: String = fixed.motion.iter().map(|(b, a)| motion_lines(b, a)).collect();
    let morphs = morph_line(&fixed.morph_seams);
    format!(
        "wrote {}: {}, {}, {} shared by 2+ objects{seams}{skin_seams}\n  {}{matched}{motion}{morphs}",
        output.display(),
        count(report.objects, "object"),
        count(report.triangles, "triangle"),
        count(report.shared_positions, "position"),
        changes_line(&fixed.changes, &fixed.options)
    )
}

/// A line on the welded positions whose objects' skin influences differ, empty where none
/// do: those open into a gap when the model is posed.
fn skin_seams_line(seams: &SkinSeams) -> String {
    let Some(example) = &seams.example else {
        return String::new();
    };
    let [x, y, z] = example.position;
    format!(
        "\n  skins: {} where objects' skin weights differ (a gap when posed), e.g. ({x}, {y}, {z}) between {} and {}",
        count(seams.positions, "shared position"),
        example.objects[0],
        example.objects[1]
    )
}

/// The morph targets whose deltas differ across the seam, as a line (empty where none do).
fn morph_line(seams: &[(String, usize)]) -> String {
    if seams.is_empty() {
        return String::new();
    }
    let each: Vec<String> = seams
        .iter()
        .map(|(name, n)| format!("{name:?} at {}", count(*n, "shared position")))
        .collect();
    format!(
        "\n  morph targets whose deltas differ across the seam (it opens while they are active): {}",
        each.join(", ")
    )
}

/// One animation's figures: `gap 0.088 (4.4% of the bounds) at 0.50 s, normals 21.70° at 0.50 s`.
fn figures(m: &SeamMotion) -> String {
    let normals = m.max_normal_angle_deg.map_or_else(
        || "normals not compared".to_owned(),
        |a| format!("normals {a:.2}° at {:.2} s", m.max_normal_angle_time),
    );
    format!(
        "gap {:.3e} ({:.2}% of the bounds) at {:.2} s, {normals}",
        m.max_gap,
        100.0 * m.max_gap_fraction,
        m.max_gap_time
    )
}

/// A name for messages: `"Walk"` or `animation 2`.
fn label(m: &SeamMotion) -> String {
    if m.name.is_empty() { format!("animation {}", m.animation) } else { format!("{:?}", m.name) }
}

/// The lines of one animation: before, then after.
fn motion_lines(before: &SeamMotion, after: &SeamMotion) -> String {
    format!(
        "\n  in motion, {} ({:.2} s, {} samples): {}\n    after: {}",
        label(before),
        before.duration,
        before.samples,
        figures(before),
        figures(after)
    )
}

/// One line saying what a fix changed: whose normals were kept, how many changed, how many
/// vertices were split, and the tangent generator.
#[must_use]
pub fn changes_line(changes: &Changes, options: &FixOptions) -> String {
    let total = changes.objects.len();
    let kept: Vec<&str> =
        changes.objects.iter().filter(|o| o.kept_normals).map(|o| o.name.as_str()).collect();
    let policy = match options.normals {
        NormalPolicy::Auto => "auto",
        NormalPolicy::SmoothShared => "smooth-shared",
        NormalPolicy::Keep => "keep",
        NormalPolicy::Recompute => "recompute",
    };
    let kept = match kept.len() {
        0 => "computed in every object".to_owned(),
        n if n == total => "kept in every object".to_owned(),
        n => {
            const SHOWN: usize = 6;
            let more = if n > SHOWN { format!(", {} more", n - SHOWN) } else { String::new() };
            let names = kept[..n.min(SHOWN)].iter().map(|s| format!("{s:?}")).collect::<Vec<_>>();
            format!(
                "kept in {n} of {total} objects ({}{more}), computed in the others",
                names.join(", ")
            )
        }
    };
    let tangents = match options.tangents {
        TangentMethod::None => "none",
        TangentMethod::Seamlit => "seamlit",
        TangentMethod::Mikktspace => "mikktspace",
    };
    format!(
        "normals ({policy}): {kept}; changed at {} of {} vertices; {} vertices split; tangents: {tangents}{}",
        changes.normals_changed(),
        changes.vertices(),
        changes.vertices_split(),
        shared_clause(&changes.shared)
    )
}

/// What the seam-only repair decided, as a clause for [`changes_line`]: `; of 120 shared
/// positions with kept normals: 80 seams repaired, 30 hard edges kept, 0 custom kept, 10
/// already equal` (empty where the repair did not run).
fn shared_clause(shared: &SharedNormals) -> String {
    if shared.positions() == 0 {
        return String::new();
    }
    format!(
        "; of {}: {} repaired, {} kept as authored hard edges, {} kept as custom, {} already equal",
        count(shared.positions(), "shared position"),
        count(shared.repaired, "seam"),
        shared.hard_edges,
        shared.custom,
        shared.agreeing
    )
}
