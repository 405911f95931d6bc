//! The toolpath model, independent of any G-code dialect.
//!
//! Coordinates are in the design's units; z = 0 is the stock surface, negative z is into the
//! material (lasers stay at z = 0). `power` is a fraction in [0, 1] of the machine's maximum
//! laser power or spindle speed; the emitter scales it to the profile's S range.

use glam::{DVec2, DVec3};

/// What a move does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// Positioning with the tool off (G0). Routers travel at safe z only.
    Rapid,
    /// A straight cutting move (G1), including plunges and retracts along z.
    Line,
    /// A helical or planar arc about `center` (xy), clockwise (G2) or not (G3).
    /// A circular or helical arc (G2/G3).
    Arc {
        /// Centre of the arc (xy).
        center: DVec2,
        /// True for counter-clockwise (G3), false for clockwise (G2).
        ccw: bool,
    },
    /// Wait in place (G4), for example spindle spin-up or a pierce.
    /// A pause (G4).
    Dwell {
        /// Length of the pause in seconds.
        seconds: f64,
    },
}

/// One move to `to` (the previous move's end, or the cut's start, is where it begins).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// What kind of move.
    pub kind: MoveKind,
    /// End point.
    pub to: DVec3,
    /// Feed in units per minute (ignored for rapids and dwells).
    pub feed: f64,
    /// Laser power or spindle speed as a fraction of the machine's maximum.
    pub power: f64,
}

/// A maximal run of moves between two retracts: one contour, hatch line group or hole.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// The stroke (or circle sequence) this cut came from, if any.
    pub source: Option<String>,
    /// The pocket this cut clears, when it clears one: cuts of one pocket may
    /// cross each other on purpose (concentric rings meeting a drilled hole). The emitter
    /// marks them in the program (`(skinpath:group N)`) so the checker can tell them from
    /// accidental crossings; unmarked cuts are judged strictly.
    pub group: Option<u32>,
    /// Where the cut begins (reached by travel).
    pub start: DVec3,
    /// The moves, in order.
    pub moves: Vec<Move>,
}

/// The kinds of operation a design can ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OperationKind {
    /// Cut along the outline of the strokes (on the waste side).
    Profile,
    /// Cut along the strokes' centre lines.
    Channel,
    /// Cut out the backboard around the design.
    Backboard,
    /// Drill or mill the holes.
    Holes,
    /// Clear the area inside the outlines (pocket or hatch).
    Fill,
    /// Carve with a V-bit along the medial axis, depth following the width.
    VCarve,
    /// Cut or engrave once along a drawn line (a stroke's spine, a shape's boundary): the
    /// emitter marks these cuts as lines, which may cross each other and themselves.
    Line,
}

/// An operation: one kind of work with one tool, its cuts in machine order.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// Operation name (from the design, or the kind).
    pub name: String,
    /// What the operation does.
    pub kind: OperationKind,
    /// The cuts in machine order.
    pub cuts: Vec<Cut>,
    /// Index of the `[[operation]]` in the design that produced it (none for the default
    /// profile of a design without operations), for messages that name what the user wrote.
    pub design_index: Option<usize>,
    /// Air assist (lasers) on during this operation.
    pub air_assist: bool,
}

/// A whole job.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Toolpath {
    /// The operations in machine order.
    pub operations: Vec<Operation>,
}

impl Toolpath {
    /// The same toolpath moved by `d` in the plane (arc centres move along).
    #[must_use]
    pub fn translated(&self, d: DVec2) -> Toolpath {
        self.mapped_xy(|p| p + d)
    }

    /// The toolpath with every point's x and y (move ends, cut starts, arc centres) mapped
    /// by `f`; z, feeds and the rest unchanged. `f` must keep distances (a translation, or
    /// one followed by a rounding far below the tolerances) for the arcs to stay arcs.
    #[must_use]
    pub fn mapped_xy(&self, f: impl Fn(DVec2) -> DVec2) -> Toolpath {
        let f3 = |p: DVec3| f(p.truncate()).extend(p.z);
        Toolpath {
            operations: self
                .operations
                .iter()
                .map(|op| Operation {
                    name: op.name.clone(),
                    kind: op.kind,
                    design_index: op.design_index,
                    air_assist: op.air_assist,
                    cuts: op
                        .cuts
                        .iter()
                        .map(|c| Cut {
                            source: c.source.clone(),
                            group: c.group,
                            start: f3(c.start),
                            moves: c
                                .moves
                                .iter()
                                .map(|m| Move {
                                    kind: match m.kind {
                                        MoveKind::Arc { center, ccw } => MoveKind::Arc {
                                            center: f(center),
                                            ccw,
                                        },
                                        k => k,
                                    },
                                    to: f3(m.to),
                                    ..*m
                                })
                                .collect(),
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}
