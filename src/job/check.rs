//! Machine profile → checker configuration, and the design boundaries a gouge check
//! protects. `sim` knows nothing of profiles; this maps one into its plain
//! [`CheckConfig`].

use super::outline::ItemOutline;
use crate::design::{
    Design, Operation, OperationKind, ProfileSide, Selection, Tags, default_operations,
};
use crate::geom::path::polygon_area;
use crate::machine::{Dialect, MachineKind, Profile};
use crate::sim::{CheckConfig, DesignBoundary, KeepSide};

/// The checker's view of `profile` for a tool of radius `tool_radius` (profile units).
/// Feeds may range from 1 unit/min up to the fastest axis; S from 0 to the profile's
/// maximum (a spindle's minimum rpm only applies while it turns, which the profile's
/// M3/M5 handling ensures).
#[must_use]
pub fn check_config(profile: &Profile, tool_radius: f64) -> CheckConfig {
    let w = &profile.work_area;
    let f = &profile.max_feed;
    let a = &profile.acceleration;
    CheckConfig {
        units: profile.units,
        kind: match profile.kind {
            MachineKind::Router => crate::sim::MachineKind::Router,
            _ => crate::sim::MachineKind::Laser,
        },
        work_min: [w.x.min(), w.y.min(), w.z.min()],
        work_max: [w.x.max(), w.y.max(), w.z.max()],
        safe_z: profile.router.as_ref().map(|r| r.safe_z).unwrap_or(0.0),
        cut_z: 0.0,
        max_rate: [f.x, f.y, f.z],
        feed_min: 1.0,
        feed_max: f.x.max(f.y).max(f.z),
        power_min: 0.0,
        power_max: profile.power.max,
        accel: [a.x, a.y, a.z],
        tool_radius,
        grbl_laser_mode: profile.dialect == Dialect::Grbl && profile.kind == MachineKind::Laser,
        // Marlin's M30 deletes a file on the SD card (Marlin/src/gcode/sd/M30.cpp, lines
        // 30-38: "M30 <filename>: Delete SD Card file") and M2 is no Marlin code: its
        // programs end without either.
        program_end_optional: profile.dialect == Dialect::Marlin,
        dialect: sim_dialect(profile.dialect),
        ..CheckConfig::default()
    }
}

/// How the checker reads a program for a profile of `dialect` (a profile without one is read
/// as the generic RS274NGC superset).
pub fn sim_dialect(dialect: Dialect) -> crate::sim::Dialect {
    match dialect {
        Dialect::Grbl => crate::sim::Dialect::Grbl,
        Dialect::Marlin => crate::sim::Dialect::Marlin,
        Dialect::Smoothie => crate::sim::Dialect::Smoothie,
        Dialect::Linuxcnc => crate::sim::Dialect::Linuxcnc,
        Dialect::None => crate::sim::Dialect::Generic,
    }
}

/// The operations a build of `design` cuts: its own, or for a design without any the ones
/// `build` chooses — a drawing (an .svg, or items with `layer` or `color`) item by item
/// ([`default_operations`]: strokes no wider than `hairline`, design units, as lines), any
/// other design one profile around the union of everything. Settings are left unset.
#[must_use]
pub fn operations_of(design: &Design, hairline: f64) -> Vec<Operation> {
    if !design.operation.is_empty() {
        return design.operation.clone();
    }
    let drawing = design.is_tagged() || design.file.to_ascii_lowercase().ends_with(".svg");
    if drawing {
        default_operations(design, hairline)
    } else {
        vec![Operation::new(OperationKind::Profile)]
    }
}

/// The outlines of the parts among `outlines`: the items that no operation of `ops` cuts
/// into. An item selected by a channel, fill, line, V-carve, holes or a profile on or inside
/// its outline is cut into by design, so a gouge check must not keep the tool off it; items
/// cut around (outside profiles — a router's default side — and backboards) or not
/// selected at all are parts. `laser` makes a profile without `side` run on the outline,
/// as the build does.
#[must_use]
pub fn part_outlines(
    design: &Design,
    ops: &[Operation],
    outlines: &[ItemOutline],
    laser: bool,
) -> Vec<ItemOutline> {
    let cuts_into = |op: &Operation| match op.kind {
        OperationKind::Profile => match op.side {
            Some(ProfileSide::Outside) => false,
            Some(ProfileSide::On | ProfileSide::Inside) => true,
            None => laser,
        },
        OperationKind::Backboard => false,
        _ => true,
    };
    let into: Vec<Selection<'_>> = ops
        .iter()
        .filter(|op| cuts_into(op))
        .map(Selection::of)
        .collect();
    let tags = design.tags();
    outlines
        .iter()
        .filter(|o| {
            let t: Tags<'_> = tags.get(o.name.as_str()).copied().unwrap_or_default();
            !into.iter().any(|s| s.selects(&o.name, t))
        })
        .cloned()
        .collect()
}

/// The outlines as boundaries for the gouge check, flattened within `tol`. With
/// `parts = true` the outlined shapes are the parts: the tool stays outside outer contours
/// (counter-clockwise) and inside the holes (clockwise inner contours of closed strokes).
/// With `parts = false` only the distance counts. `mm_per_unit` converts the design's units
/// to the millimetres the checker works in.
#[must_use]
pub fn design_boundaries(
    outlines: &[ItemOutline],
    parts: bool,
    tol: f64,
    mm_per_unit: f64,
) -> Vec<DesignBoundary> {
    outlines
        .iter()
        .flat_map(|o| o.contours.iter())
        .map(|p| {
            let pts: Vec<_> = p
                .flatten(tol)
                .into_iter()
                .map(|q| q * mm_per_unit)
                .collect();
            let keep = if !parts {
                KeepSide::Either
            } else if polygon_area(&pts) >= 0.0 {
                KeepSide::Outside
            } else {
                KeepSide::Inside
            };
            DesignBoundary::new(&pts, keep)
        })
        .collect()
}
