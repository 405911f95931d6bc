//! Coordinate systems and offsets: G54–G59.3 origins, G92 and its parameters, and the
//! non-modal codes (G4, G10, G28/G30, G52, G53, G92.x).

use super::*;

impl Interp<'_, '_> {
    pub(super) fn cs_origin(&self, n: usize) -> DVec3 {
        let base = P_G54 + 20 * (n - 1);
        DVec3::new(
            self.params[base],
            self.params[base + 1],
            self.params[base + 2],
        )
    }

    pub(super) fn select_cs(&mut self, n: usize) {
        self.st.cs = n;
        self.params[P_CS] = n as f64;
        self.st.g5x = self.cs_origin(n);
    }

    pub(super) fn g92_stored(&self) -> DVec3 {
        DVec3::new(
            self.params[P_G92],
            self.params[P_G92 + 1],
            self.params[P_G92 + 2],
        )
    }

    pub(super) fn store(&mut self, base: usize, v: DVec3) {
        self.params[base] = v.x;
        self.params[base + 1] = v.y;
        self.params[base + 2] = v.z;
    }

    /// G10, G28, G30, G52, G53 (handled with the motion), G92*.
    pub(super) fn nonmodal(&mut self, c: i64, b: &mut Block) {
        let k = self.st.k();
        let axes = |b: &Block| -> [Option<f64>; 3] {
            [b.val('X'), b.val('Y'), b.val('Z')].map(|v| v.map(|v| v * k))
        };
        match c {
            100 => {
                b.axes_used = true;
                b.used_l = true;
                b.used_p = true;
                b.used_r = true;
                let l = b.val('L').map(|l| l.round() as i64);
                let p = b.val('P').map(|p| p.round() as i64);
                let a = axes(b);
                match (l, p) {
                    (Some(2) | Some(20), Some(p)) if (0..=9).contains(&p) => {
                        let n = if p == 0 { self.st.cs } else { p as usize };
                        if b.val('R').is_some_and(|r| r != 0.0) {
                            self.err(
                                "unsupported-code",
                                None,
                                "G10 L2 R (coordinate system rotation) is not supported".into(),
                            );
                        }
                        let mut o = self.cs_origin(n);
                        for i in 0..3 {
                            if let Some(v) = a[i] {
                                o[i] = if l == Some(2) {
                                    v
                                } else {
                                    self.st.pos[i] - self.st.g92[i] - self.st.tlo[i] - v
                                };
                            }
                        }
                        self.store(P_G54 + 20 * (n - 1), o);
                        if n == self.st.cs {
                            self.st.g5x = o;
                        }
                    }
                    (Some(1) | Some(10) | Some(11), Some(p)) if p >= 0 => {
                        let mut t = self.tool(p as u32).copied().unwrap_or(ToolEntry {
                            number: p as u32,
                            ..Default::default()
                        });
                        if let Some(z) = a[2] {
                            t.z = if l == Some(1) {
                                z
                            } else {
                                self.st.pos.z - self.st.g5x.z - self.st.g92.z - z
                            };
                        }
                        if let Some(x) = a[0] {
                            t.x = if l == Some(1) {
                                x
                            } else {
                                self.st.pos.x - self.st.g5x.x - self.st.g92.x - x
                            };
                        }
                        if let Some(r) = b.val('R') {
                            t.diameter = 2.0 * r * k;
                        }
                        // The tool table is configuration; G10 L1 edits a copy for this run.
                        self.tools.retain(|e| e.number != t.number);
                        self.tools.push(t);
                    }
                    _ => self.err(
                        "invalid-value",
                        None,
                        "G10 needs L1, L2, L10, L11 or L20 with a valid P".into(),
                    ),
                }
            }
            280 | 300 => {
                b.axes_used = true;
                let stored = DVec3::from_array(std::array::from_fn(|i| {
                    self.params[if c == 280 { P_G28 } else { P_G30 } + i]
                }));
                let a = axes(b);
                let mut target = stored;
                if a.iter().any(Option::is_some) {
                    let mid = self.target(b);
                    self.straight(MotionKind::Rapid, mid);
                    for i in 0..3 {
                        if a[i].is_none() {
                            target[i] = self.st.pos[i];
                        }
                    }
                }
                self.straight(MotionKind::Rapid, target);
            }
            281 | 301 => {
                let p = self.st.pos;
                self.store(if c == 281 { P_G28 } else { P_G30 }, p);
            }
            520 | 920 => {
                b.axes_used = true;
                let a = axes(b);
                let mut o = self.st.g92;
                for i in 0..3 {
                    if let Some(v) = a[i] {
                        o[i] = if c == 520 {
                            v
                        } else {
                            self.st.pos[i] - self.st.g5x[i] - self.st.tlo[i] - v
                        };
                    }
                }
                self.st.g92 = o;
                self.store(P_G92, o);
            }
            921 => {
                self.st.g92 = DVec3::ZERO;
                self.store(P_G92, DVec3::ZERO);
            }
            922 => self.st.g92 = DVec3::ZERO,
            923 => self.st.g92 = self.g92_stored(),
            530 => b.machine_coords = true,
            _ => {}
        }
    }
}
