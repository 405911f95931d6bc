//! DXF read back by the tests' own group-code reader (tests/api/emit_dxf.rs confirms it
//! against ezdxf, the reference Python DXF library, where that is installed).

use glam::DVec2;

/// A DXF drawing as read back: what the checks below compare with the toolpath.
#[derive(Debug, PartialEq)]
pub struct Drawing {
    /// `$INSUNITS` of the header (4 = millimetres).
    pub insunits: Option<i64>,
    /// `$EXTMIN` and `$EXTMAX` of the header (x, y).
    pub extents: Option<(DVec2, DVec2)>,
    /// The names in the LAYER table.
    pub layers: Vec<String>,
    /// Every POLYLINE of the ENTITIES section.
    pub polylines: Vec<Poly>,
}

/// A polyline read back: layer, closed flag, vertices with bulges.
pub type Poly = (String, bool, Vec<(DVec2, f64)>);

/// Reads the drawing with the test's own group-code reader, which knows the DXF reference
/// (code/value line pairs; HEADER variables after code 9; LAYER table entries named by code 2;
/// POLYLINE with layer 8 and flags 70 (bit 1 = closed), then VERTEX entities with 10/20 and
/// bulge 42 until SEQEND; the file ends with `0 EOF`) and shares no code with the writer.
/// Every malformed pair fails the test.
pub fn load(text: &str) -> Drawing {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    assert!(lines.len().is_multiple_of(2), "odd number of lines\n{text}");
    let pairs: Vec<(i32, &str)> = lines
        .chunks(2)
        .map(|p| {
            (
                p[0].parse()
                    .unwrap_or_else(|e| panic!("group code {:?}: {e}", p[0])),
                p[1],
            )
        })
        .collect();
    assert_eq!(pairs.last(), Some(&(0, "EOF")), "the file ends with 0 EOF");
    let num = |v: &str| -> f64 { v.parse().unwrap_or_else(|e| panic!("number {v:?}: {e}")) };
    let mut d = Drawing {
        insunits: None,
        extents: None,
        layers: Vec::new(),
        polylines: Vec::new(),
    };
    let (mut section, mut var, mut entity) = ("", "", "");
    let (mut ext, mut depth) = ([DVec2::ZERO; 2], 0);
    for (i, &(code, value)) in pairs.iter().enumerate() {
        if code == 0 {
            entity = value;
            match value {
                "SECTION" => {
                    depth += 1;
                    section = pairs.get(i + 1).filter(|p| p.0 == 2).map_or("", |p| p.1);
                }
                "ENDSEC" => depth -= 1,
                "POLYLINE" => d.polylines.push((String::new(), false, Vec::new())),
                "VERTEX" => {
                    let poly = d.polylines.last_mut().expect("VERTEX after a POLYLINE");
                    poly.2.push((DVec2::ZERO, 0.0));
                }
                _ => {}
            }
            assert!((0..=1).contains(&depth), "sections balanced");
            continue;
        }
        match (section, entity, code) {
            ("HEADER", _, 9) => var = value,
            ("HEADER", _, 70) if var == "$INSUNITS" => d.insunits = value.parse().ok(),
            ("HEADER", _, 10 | 20) if var == "$EXTMIN" || var == "$EXTMAX" => {
                let k = usize::from(var == "$EXTMAX");
                if code == 10 {
                    ext[k].x = num(value)
                } else {
                    ext[k].y = num(value)
                }
                d.extents = Some((ext[0], ext[1]));
            }
            ("TABLES", "LAYER", 2) => d.layers.push(value.to_string()),
            ("ENTITIES", "POLYLINE", 8) => d.polylines.last_mut().unwrap().0 = value.to_string(),
            ("ENTITIES", "POLYLINE", 70) => {
                d.polylines.last_mut().unwrap().1 = value.parse::<i64>().unwrap() & 1 == 1
            }
            ("ENTITIES", "VERTEX", 10 | 20 | 42) => {
                let v = d.polylines.last_mut().unwrap().2.last_mut().unwrap();
                match code {
                    10 => v.0.x = num(value),
                    20 => v.0.y = num(value),
                    _ => v.1 = num(value),
                }
            }
            _ => {}
        }
    }
    d
}
