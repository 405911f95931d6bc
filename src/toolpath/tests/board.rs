//! Backboard bridges ([`crate::toolpath::board`]): pieces apart are joined into one at the
//! documented bridge width, measured across the gaps.

use crate::geom::DVec2;
use crate::geom::interop::{flatten_pline, pline_from_points};
use crate::toolpath::board::{BRIDGE_WIDTH_MM, bridged, pieces};
use crate::toolpath::region::Region;

/// A square [x, x + a] × [y, y + a].
fn square(x: f64, y: f64, a: f64) -> Region {
    let pts = [
        DVec2::new(x, y),
        DVec2::new(x + a, y),
        DVec2::new(x + a, y + a),
        DVec2::new(x, y + a),
    ];
    Region::from_contours(vec![pline_from_points(&pts, true)])
}

/// The lengths of the intersections of the vertical line x = `x` with the region's
/// contours (flattened), sorted: crossings of the edges, paired.
fn chords_at_x(region: &Region, x: f64) -> Vec<f64> {
    let mut ys = Vec::new();
    for c in &region.contours {
        let pts = flatten_pline(c, 1e-3);
        for k in 0..pts.len() {
            let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
            if (a.x <= x) != (b.x <= x) {
                ys.push(a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x));
            }
        }
    }
    ys.sort_by(f64::total_cmp);
    ys.chunks(2).map(|p| p[1] - p[0]).collect()
}

/// Three squares apart in an L are joined by two bridges (a spanning tree: shortest gaps,
/// no cycle) into one piece; across the middle of each gap the board is exactly the bridge
/// width (a straight bridge of width w cut by a line across it).
#[test]
fn bridges_join_pieces_at_the_documented_width() {
    let w = BRIDGE_WIDTH_MM;
    let parts = [
        square(0.0, 0.0, 40.0),
        square(70.0, 0.0, 40.0),
        square(0.0, 90.0, 40.0),
    ];
    let board = Region::union(&parts, 1e-3);
    assert_eq!(pieces(&board).len(), 3);
    let (one, bridges) = bridged(&board, w, 1.0, 1e-3, 1e-4);
    assert_eq!(pieces(&one).len(), 1);
    assert_eq!(bridges.len(), 2, "{bridges:?}");
    // Gap of 30 between the first two squares (x in 40..70): the bridge crosses x = 55.
    let chords = chords_at_x(&one, 55.0);
    assert_eq!(chords.len(), 1, "{chords:?}");
    assert!((chords[0] - w).abs() < 1e-2, "{chords:?}");
    // Gap of 50 up to the third (y in 40..90): horizontal chords across y = 65.
    let turned: Vec<_> = one
        .contours
        .iter()
        .map(|c| {
            let pts: Vec<DVec2> = flatten_pline(c, 1e-3)
                .into_iter()
                .map(|p| DVec2::new(p.y, -p.x))
                .collect();
            pline_from_points(&pts, true)
        })
        .collect();
    let chords = chords_at_x(&Region::from_contours(turned), 65.0);
    assert_eq!(chords.len(), 1, "{chords:?}");
    assert!((chords[0] - w).abs() < 1e-2, "{chords:?}");
    // The bridged board holds every piece (shrunk a little: their edges are its edges),
    // and nothing was bridged for one piece.
    assert!(one.holds(&board.offset(-1e-2, 1e-4)));
    let (same, none) = bridged(&parts[0], w, 1.0, 1e-3, 1e-4);
    assert!(none.is_empty() && same.contours.len() == 1);
    assert!((same.area() - parts[0].area()).abs() < 1e-9);
    // Width 0 leaves the pieces apart.
    let (apart, none) = bridged(&board, 0.0, 1.0, 1e-3, 1e-4);
    assert!(none.is_empty() && pieces(&apart).len() == 3);
}

mod props {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

        /// Squares scattered apart, bridged: one piece that holds them all, and a disk of
        /// diameter 0.9·w fits through every bridge (the opening by 0.45·w is still one
        /// piece; the exact width across a bridge is tested above).
        #[test]
        fn bridged_boards_are_one_piece_a_disk_wide(
            cells in proptest::collection::btree_set((0u8..5, 0u8..5), 2..6),
            w in 4.0f64..12.0,
        ) {
            let parts: Vec<Region> = cells
                .iter()
                .map(|&(i, j)| square(f64::from(i) * 50.0, f64::from(j) * 50.0, 25.0))
                .collect();
            let board = Region::union(&parts, 1e-3);
            let (one, _) = bridged(&board, w, 1.0, 1e-3, 1e-4);
            prop_assert_eq!(pieces(&one).len(), 1);
            prop_assert!(one.holds(&board.offset(-1e-2, 1e-4)));
            let r = 0.45 * w;
            let opened = one.offset(-r, 1e-4).offset(r, 1e-4);
            prop_assert_eq!(pieces(&opened).len(), 1);
        }
    }
}
