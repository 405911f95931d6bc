//! Interval arithmetic and second-order jets of intervals: enclosures of a function's value
//! and first two derivatives over a parameter range (interval arithmetic as in Moore,
//! Kearfott & Cloud, *Introduction to Interval Analysis*, SIAM 2009; the jet rules are the
//! product and chain rules applied to enclosures).

/// A closed real interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Interval {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
}

impl Interval {
    pub(crate) fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }
    pub(crate) fn pt(x: f64) -> Interval {
        Interval::new(x, x)
    }
    pub(crate) fn add(self, o: Interval) -> Interval {
        Interval::new(self.lo + o.lo, self.hi + o.hi)
    }
    pub(crate) fn sub(self, o: Interval) -> Interval {
        Interval::new(self.lo - o.hi, self.hi - o.lo)
    }
    /// The product's range: the least and greatest of the four end products (each
    /// comparison picks one of its operands; the operands here are finite).
    pub(crate) fn mul(self, o: Interval) -> Interval {
        let (a, b, c, d) = (
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        );
        let min = |x: f64, y: f64| if x < y { x } else { y };
        let max = |x: f64, y: f64| if x > y { x } else { y };
        Interval::new(min(min(a, b), min(c, d)), max(max(a, b), max(c, d)))
    }
    /// k·x: the ends scaled, swapped when k < 0.
    pub(crate) fn scale(self, k: f64) -> Interval {
        if k >= 0.0 {
            Interval::new(self.lo * k, self.hi * k)
        } else {
            Interval::new(self.hi * k, self.lo * k)
        }
    }
    /// 1/x; NaN-free only when 0 ∉ x (callers check `positive`).
    pub(crate) fn recip(self) -> Interval {
        Interval::new(1.0 / self.hi, 1.0 / self.lo)
    }
    pub(crate) fn sqrt(self) -> Interval {
        Interval::new(self.lo.max(0.0).sqrt(), self.hi.max(0.0).sqrt())
    }
    pub(crate) fn positive(self) -> bool {
        self.lo > 0.0
    }
    pub(crate) fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }
    pub(crate) fn clip_unit(self) -> Interval {
        Interval::new(self.lo.max(-1.0), self.hi.min(1.0))
    }
}

/// A second-order jet (f, f′, f″) of interval enclosures.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jet {
    pub(crate) v: Interval,
    pub(crate) d1: Interval,
    pub(crate) d2: Interval,
}

impl Jet {
    pub(crate) fn add(self, o: Jet) -> Jet {
        Jet {
            v: self.v.add(o.v),
            d1: self.d1.add(o.d1),
            d2: self.d2.add(o.d2),
        }
    }
    pub(crate) fn sub(self, o: Jet) -> Jet {
        Jet {
            v: self.v.sub(o.v),
            d1: self.d1.sub(o.d1),
            d2: self.d2.sub(o.d2),
        }
    }
    pub(crate) fn scale(self, k: f64) -> Jet {
        Jet {
            v: self.v.scale(k),
            d1: self.d1.scale(k),
            d2: self.d2.scale(k),
        }
    }
    /// (fg)′ = f′g + fg′, (fg)″ = f″g + 2f′g′ + fg″.
    pub(crate) fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v.mul(o.v),
            d1: self.d1.mul(o.v).add(self.v.mul(o.d1)),
            d2: self
                .d2
                .mul(o.v)
                .add(self.d1.mul(o.d1).scale(2.0))
                .add(self.v.mul(o.d2)),
        }
    }
    /// f², [`Self::mul`] of `self` by itself with each product taken once: the same
    /// intervals bit for bit (the two cross terms of a product are equal).
    pub(crate) fn sqr(self) -> Jet {
        let d1v = self.d1.mul(self.v);
        let d2v = self.d2.mul(self.v);
        Jet {
            v: self.v.mul(self.v),
            d1: d1v.add(d1v),
            d2: d2v.add(self.d1.mul(self.d1).scale(2.0)).add(d2v),
        }
    }
    /// g = 1/f: g′ = −f′ g², g″ = 2 f′² g³ − f″ g². Requires f > 0.
    pub(crate) fn recip(self) -> Jet {
        let g = self.v.recip();
        let g2 = g.mul(g);
        Jet {
            v: g,
            d1: self.d1.mul(g2).scale(-1.0),
            d2: self
                .d1
                .mul(self.d1)
                .mul(g2.mul(g))
                .scale(2.0)
                .sub(self.d2.mul(g2)),
        }
    }
    /// g = √f: g′ = f′/(2g), g″ = (f″ − 2g′²)/(2g). Requires f > 0.
    pub(crate) fn sqrt(self) -> Jet {
        let g = self.v.sqrt();
        let inv2g = g.scale(2.0).recip();
        let g1 = self.d1.mul(inv2g);
        Jet {
            v: g,
            d1: g1,
            d2: self.d2.sub(g1.mul(g1).scale(2.0)).mul(inv2g),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn iv(a: f64, b: f64) -> Interval {
        Interval::new(a.min(b), a.max(b))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// The product and the scaled interval hold every product of their members, and
        /// their ends are products of ends (the tightest enclosure).
        #[test]
        fn interval_product_encloses_the_products(
            a in (-1e3f64..1e3, -1e3f64..1e3),
            b in (-1e3f64..1e3, -1e3f64..1e3),
            f in (0.0f64..=1.0, 0.0f64..=1.0),
            k in -5.0f64..5.0,
        ) {
            let (x, y) = (iv(a.0, a.1), iv(b.0, b.1));
            let p = x.mul(y);
            let ends = [x.lo * y.lo, x.lo * y.hi, x.hi * y.lo, x.hi * y.hi];
            prop_assert!(ends.contains(&p.lo) && ends.contains(&p.hi));
            let (u, v) = (x.lo + f.0 * (x.hi - x.lo), y.lo + f.1 * (y.hi - y.lo));
            prop_assert!(p.lo <= u * v && u * v <= p.hi, "{:?} {}", p, u * v);
            let s = x.scale(k);
            prop_assert!(s.lo <= s.hi && s.lo <= u * k && u * k <= s.hi);
            prop_assert_eq!(s, x.mul(Interval::pt(k)));
        }

        /// The square of a jet is its product with itself, bit for bit.
        #[test]
        fn jet_square_is_the_product_with_itself(
            v in (-1e3f64..1e3, -1e3f64..1e3),
            d1 in (-1e3f64..1e3, -1e3f64..1e3),
            d2 in (-1e3f64..1e3, -1e3f64..1e3),
        ) {
            let j = Jet { v: iv(v.0, v.1), d1: iv(d1.0, d1.1), d2: iv(d2.0, d2.1) };
            let (sq, m) = (j.sqr(), j.mul(j));
            prop_assert_eq!((sq.v, sq.d1, sq.d2), (m.v, m.d1, m.d2));
        }
    }
}
