//! Canned cycles (G73, G81–G86, G88, G89) expanded into moves as RS274NGC does, with G98/G99
//! retract.

use super::*;

impl Interp<'_, '_> {
    /// Canned cycles in the XY plane, expanded as LinuxCNC does (`convert_cycle_xy`):
    /// preliminary rapid up to R when below it, then per repeat (L): rapid in XY at the
    /// current height, rapid down to R, the cycle's own moves, retract to R (G99) or to the
    /// height before the cycle (G98).
    pub(super) fn cycle(&mut self, code: i64, b: &mut Block) {
        let k = self.st.k();
        b.used_r = true;
        b.used_l = true;
        b.used_p = true;
        b.used_q = true;
        if self.st.plane != Plane::Xy {
            self.err(
                "unsupported-code",
                None,
                format!("G{} outside the XY plane is not supported", fmt_code(code)),
            );
            return;
        }
        if matches!(code, 870 | 760 | 840 | 740) && code != 840 {
            self.err(
                "unsupported-code",
                None,
                format!(
                    "G{} is not supported: its motion is skipped",
                    fmt_code(code)
                ),
            );
            return;
        }
        if let Some(r) = b.val('R') {
            self.st.cycle_r = Some(r);
        }
        if let Some(z) = b.val('Z') {
            self.st.cycle_z = Some(z);
        }
        if let Some(q) = b.val('Q') {
            self.st.cycle_q = Some(q);
        }
        if let Some(p) = b.val('P') {
            self.st.cycle_p = Some(p);
        }
        let (Some(r), Some(z)) = (self.st.cycle_r, self.st.cycle_z) else {
            self.err(
                "invalid-value",
                None,
                format!("G{} needs R and Z", fmt_code(code)),
            );
            return;
        };
        let off = self.st.offset();
        let old_z = *self.st.cycle_start_z.get_or_insert(self.st.pos.z);
        // R and Z in machine coordinates; incremental (G91): R from the Z where the series of
        // cycles started, Z from R (as rs274 does).
        let (r_m, z_m) = if self.st.absolute {
            (r * k + off.z, z * k + off.z)
        } else {
            (old_z + r * k, old_z + r * k + z * k)
        };
        if z_m > r_m {
            self.err(
                "invalid-value",
                None,
                "canned cycle bottom Z is above the R plane".into(),
            );
            return;
        }
        let q = self.st.cycle_q.map(|q| q * k);
        if matches!(code, 730 | 830) && q.is_none_or(|q| q <= 0.0) {
            self.err(
                "invalid-value",
                None,
                format!("G{} needs Q > 0 (peck depth)", fmt_code(code)),
            );
            return;
        }
        let dwell = self.st.cycle_p.unwrap_or(0.0);
        let reps = b.val('L').map_or(1, |l| l.round().max(0.0) as usize);
        if self.st.pos.z < r_m {
            let p = DVec3::new(self.st.pos.x, self.st.pos.y, r_m);
            self.straight(MotionKind::Rapid, p);
        }
        let clear = if self.st.retract_r {
            r_m
        } else {
            old_z.max(r_m)
        };
        let mut cur_z = self.st.pos.z;
        for rep in 0..reps {
            // Each repeat after the first counts against the loop budget.
            if rep > 0 && !self.count_iteration() {
                return;
            }
            // X Y (or polar @ ^) of this hole; in G91 each repeat moves by X Y again.
            let mut xy = self.st.pos;
            if b.val('@').is_some() || b.val('^').is_some() {
                let mut pb = b.clone();
                pb.vals[2] = None;
                xy = self.target(&pb);
            } else {
                for (i, c) in ['X', 'Y'].into_iter().enumerate() {
                    if let Some(v) = b.val(c) {
                        xy[i] = if self.st.absolute {
                            v * k + off[i]
                        } else {
                            self.st.pos[i] + v * k
                        };
                    }
                }
            }
            self.straight(MotionKind::Rapid, DVec3::new(xy.x, xy.y, cur_z));
            if cur_z != r_m {
                self.straight(MotionKind::Rapid, DVec3::new(xy.x, xy.y, r_m));
            }
            let at = |z: f64| DVec3::new(xy.x, xy.y, z);
            match code {
                810 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    self.straight(MotionKind::Rapid, at(clear));
                }
                820 | 890 | 860 | 880 | 850 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    if code != 850 && dwell > 0.0 {
                        let m = self.motion(MotionKind::Dwell { seconds: dwell }, at(z_m), None);
                        self.emit(m);
                    }
                    match code {
                        850 | 890 => {
                            self.straight(MotionKind::Feed, at(r_m));
                            self.straight(MotionKind::Rapid, at(clear));
                        }
                        _ => self.straight(MotionKind::Rapid, at(clear)),
                    }
                }
                840 => {
                    self.straight(MotionKind::Feed, at(z_m));
                    self.straight(MotionKind::Feed, at(r_m));
                    self.straight(MotionKind::Rapid, at(clear));
                }
                730 | 830 => {
                    let q = q.unwrap_or(1.0);
                    let mut depth = r_m;
                    while depth > z_m {
                        // Each peck after the first counts against the loop budget.
                        if depth < r_m && !self.count_iteration() {
                            return;
                        }
                        let next = (depth - q).max(z_m);
                        if code == 830 && depth < r_m {
                            self.straight(MotionKind::Rapid, at(depth + PECK_CLEARANCE_MM));
                        }
                        self.straight(MotionKind::Feed, at(next));
                        depth = next;
                        if depth > z_m {
                            if code == 830 {
                                self.straight(MotionKind::Rapid, at(r_m));
                            } else {
                                self.straight(MotionKind::Rapid, at(depth + PECK_CLEARANCE_MM));
                            }
                        }
                    }
                    self.straight(MotionKind::Rapid, at(clear));
                }
                _ => {}
            }
            cur_z = clear;
        }
    }
}
