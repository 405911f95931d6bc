//! Clearing rings of dense channel regions (dumped from builds of script lettering) stay
//! inside the channel, at least the tool radius from its walls.

/// The channel regions of script lettering (width 10 along overlapping strokes: "neon" at
/// 30 mm, "Hello" at 80 mm), dumped from the build as cavalier polylines: the dense union
/// of the strokes' swept regions. Clearing rings offset from them once cut across a
/// letter's counter with single chords (7.9 and 14 mm) whose ends and middles lay in the
/// channel: the router would have cut outside the channel, and nothing in the program
/// shows it. Every point of every ring must lie in the channel, at least the tool radius
/// (the first offset) from its walls, within twice the build's tolerance; measured with geo's
/// Euclidean distance to the walls flattened within 1 µm.
#[test]
fn clearing_rings_of_script_lettering_stay_in_the_channel() {
    use crate::geom::interop::flatten_pline;
    use crate::toolpath::ops::concentric;
    use crate::toolpath::region::Region;
    use cavalier_contours::polyline::{PlineSourceMut, PlineVertex, Polyline};
    use geo::{Distance, Euclidean};
    for name in ["script_neon_channel_region", "script_hello_channel_region"] {
        let text = std::fs::read_to_string(format!(
            "{}/tests/robust_data/{name}.json",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        let j: serde_json::Value = serde_json::from_str(&text).unwrap();
        let num = |k: &str| j[k].as_f64().unwrap();
        let contours: Vec<Polyline<f64>> = j["contours"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let mut pl = Polyline::new_closed();
                for v in c.as_array().unwrap() {
                    let v: Vec<f64> = serde_json::from_value(v.clone()).unwrap();
                    pl.add_vertex(PlineVertex::new(v[0], v[1], v[2]));
                }
                pl
            })
            .collect();
        let walls: Vec<geo::LineString<f64>> = contours
            .iter()
            .map(|c| {
                let mut pts: Vec<geo::Coord<f64>> = flatten_pline(c, 1e-6)
                    .into_iter()
                    .map(|p| geo::Coord { x: p.x, y: p.y })
                    .collect();
                pts.push(pts[0]);
                geo::LineString::new(pts)
            })
            .collect();
        let region = Region::from_contours(contours);
        let (first, eps) = (num("first"), num("eps"));
        let rings = concentric(&region, first, num("stepover"), num("reach"), 10_000, eps);
        assert!(rings.len() > 3, "{name}: {} rings", rings.len());
        // Rings made by geo's buffer (`Region::buffered`) offset the walls flattened within
        // the build's tolerance (10·eps), and flatten their round joins within it: twice
        // that bounds how much nearer than the tool radius they may come to a wall.
        let tol = 2.0 * 10.0 * eps;
        for (k, ring) in rings.iter().enumerate() {
            // Points at most 0.25 apart along every segment (a chord's middle included).
            let points = ring.segs.iter().flat_map(|s| {
                let n = 2 * (s.length(1e-6) / 0.5).ceil().max(1.0) as usize;
                (0..n).map(move |i| s.eval(i as f64 / n as f64))
            });
            for p in points {
                assert!(
                    region.contains(p),
                    "{name} ring {k}: {p} outside the channel"
                );
                let q = geo::Point::new(p.x, p.y);
                let wall = walls
                    .iter()
                    .map(|w| Euclidean.distance(&q, w))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    wall >= first - tol,
                    "{name} ring {k}: {p} is {wall} from a wall, tool radius {first}"
                );
            }
        }
    }
}
