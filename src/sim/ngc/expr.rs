//! Expressions: binary operators (with LinuxCNC's precedence), unary functions, parameter
//! references, and their evaluation against a [`ParamSource`].

use super::*;

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `**`
    Pow,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `MOD`
    Mod,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `EQ`
    Eq,
    /// `NE`
    Ne,
    /// `GT`
    Gt,
    /// `GE`
    Ge,
    /// `LT`
    Lt,
    /// `LE`
    Le,
    /// `AND`
    And,
    /// `OR`
    Or,
    /// `XOR`
    Xor,
}

impl BinOp {
    /// LinuxCNC's precedence levels (higher binds tighter).
    pub fn precedence(self) -> u8 {
        match self {
            BinOp::Pow => 6,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 5,
            BinOp::Add | BinOp::Sub => 4,
            BinOp::Eq | BinOp::Ne | BinOp::Gt | BinOp::Ge | BinOp::Lt | BinOp::Le => 3,
            BinOp::And | BinOp::Or | BinOp::Xor => 2,
        }
    }
}

/// A unary function taking one bracketed argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    /// `ABS`
    Abs,
    /// `ACOS` (degrees)
    Acos,
    /// `ASIN` (degrees)
    Asin,
    /// `COS` (of degrees)
    Cos,
    /// `EXP`
    Exp,
    /// `FIX`: round down
    Fix,
    /// `FUP`: round up
    Fup,
    /// `LN`
    Ln,
    /// `ROUND`: to the nearest integer
    Round,
    /// `SIN` (of degrees)
    Sin,
    /// `SQRT`
    Sqrt,
    /// `TAN` (of degrees)
    Tan,
}

pub(super) const FUNCS: [(&str, Func); 12] = [
    ("abs", Func::Abs),
    ("acos", Func::Acos),
    ("asin", Func::Asin),
    ("cos", Func::Cos),
    ("exp", Func::Exp),
    ("fix", Func::Fix),
    ("fup", Func::Fup),
    ("ln", Func::Ln),
    ("round", Func::Round),
    ("sin", Func::Sin),
    ("sqrt", Func::Sqrt),
    ("tan", Func::Tan),
];

/// A parameter reference: numbered (`#expr`) or named (`#<name>`, lower-cased, spaces
/// removed; a leading `_` makes it global).
#[derive(Clone, Debug, PartialEq)]
pub enum ParamRef {
    /// `#expr`: the parameter numbered by the value.
    Num(Box<Expr>),
    /// `#<name>`: the name lower-cased, spaces removed.
    Named(String),
}

/// An expression tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number.
    Num(f64),
    /// A parameter value.
    Param(ParamRef),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A unary function.
    Func(Func, Box<Expr>),
    /// `ATAN[y]/[x]`: the angle of (x, y) in degrees.
    Atan(Box<Expr>, Box<Expr>),
    /// `EXISTS[#<name>]`.
    Exists(String),
    /// Binary operations folded from the left: `Chain(a, [(op₁, b), (op₂, c)])` is
    /// `(a op₁ b) op₂ c`. The parser makes one chain of a run of operators that LinuxCNC
    /// reduces left to right (all its binary operators are left-associative), so a flat sum
    /// of any length is one node evaluated in a loop, and the tree's depth is bounded by
    /// [`MAX_NESTING`] times the number of precedence levels.
    Chain(Box<Expr>, Vec<(BinOp, Expr)>),
}

/// Where expressions read parameters.
pub trait ParamSource {
    /// Numbered parameter `n` (already checked to be in 0..=[`MAX_PARAMETER`]).
    fn numbered(&self, n: i64) -> f64;
    /// Named parameter (lower case), `None` when it does not exist.
    fn named(&self, name: &str) -> Option<f64>;
}

/// Rounds a parameter number: it must be within 1e-4 of an integer in 0..=5601.
pub fn param_index(v: f64) -> Result<i64, String> {
    let r = v.round();
    if (v - r).abs() > TOLERANCE_EQUAL || !(0.0..=MAX_PARAMETER as f64).contains(&r) {
        return Err(format!(
            "parameter number {v} is not an integer in 0..={MAX_PARAMETER}"
        ));
    }
    Ok(r as i64)
}

impl Expr {
    /// Evaluates with LinuxCNC's semantics: angles in degrees, relational and logical
    /// operators give 1.0 or 0.0, `MOD` gives a result with the sign of the divisor's
    /// magnitude (non-negative), division by zero and domain errors are errors.
    pub fn eval(&self, p: &dyn ParamSource) -> Result<f64, String> {
        match self {
            Expr::Num(v) => Ok(*v),
            Expr::Param(ParamRef::Num(e)) => Ok(p.numbered(param_index(e.eval(p)?)?)),
            Expr::Param(ParamRef::Named(n)) => p
                .named(n)
                .ok_or_else(|| format!("named parameter #<{n}> is not defined")),
            Expr::Neg(e) => Ok(-e.eval(p)?),
            Expr::Exists(n) => Ok(if p.named(n).is_some() { 1.0 } else { 0.0 }),
            Expr::Atan(y, x) => Ok(y.eval(p)?.atan2(x.eval(p)?).to_degrees()),
            Expr::Func(f, e) => func(*f, e.eval(p)?),
            Expr::Chain(a, rest) => {
                let mut v = a.eval(p)?;
                for (op, b) in rest {
                    v = binary(*op, v, b.eval(p)?)?;
                }
                Ok(v)
            }
        }
    }
}

pub(super) fn func(f: Func, v: f64) -> Result<f64, String> {
    let deg = PI / 180.0;
    Ok(match f {
        Func::Abs => v.abs(),
        Func::Acos => {
            if !(-1.0..=1.0).contains(&v) {
                return Err(format!("ACOS argument {v} is outside [-1, 1]"));
            }
            v.acos() / deg
        }
        Func::Asin => {
            if !(-1.0..=1.0).contains(&v) {
                return Err(format!("ASIN argument {v} is outside [-1, 1]"));
            }
            v.asin() / deg
        }
        Func::Cos => (v * deg).cos(),
        Func::Exp => v.exp(),
        Func::Fix => v.floor(),
        Func::Fup => v.ceil(),
        Func::Ln => {
            if v <= 0.0 {
                return Err(format!("LN argument {v} is not positive"));
            }
            v.ln()
        }
        // LinuxCNC: (int)(v + 0.5) for v ≥ 0, (int)(v − 0.5) below: halves away from zero.
        Func::Round => v.round(),
        Func::Sin => (v * deg).sin(),
        Func::Sqrt => {
            if v < 0.0 {
                return Err(format!("SQRT argument {v} is negative"));
            }
            v.sqrt()
        }
        Func::Tan => (v * deg).tan(),
    })
}

pub(super) fn binary(op: BinOp, a: f64, b: f64) -> Result<f64, String> {
    let t = |c: bool| if c { 1.0 } else { 0.0 };
    Ok(match op {
        BinOp::Pow => {
            if a < 0.0 && b.fract() != 0.0 {
                return Err(format!(
                    "{a} ** {b}: a negative base needs an integer exponent"
                ));
            }
            if a == 0.0 && b < 0.0 {
                return Err("0 ** a negative exponent is a division by zero".into());
            }
            a.powf(b)
        }
        BinOp::Mul => a * b,
        BinOp::Div => {
            if b == 0.0 {
                return Err("division by zero".into());
            }
            a / b
        }
        BinOp::Mod => {
            if b == 0.0 {
                return Err("MOD by zero".into());
            }
            let m = a % b;
            if m < 0.0 { m + b.abs() } else { m }
        }
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Eq => t((a - b).abs() < TOLERANCE_EQUAL),
        BinOp::Ne => t((a - b).abs() >= TOLERANCE_EQUAL),
        BinOp::Gt => t(a > b),
        BinOp::Ge => t(a >= b),
        BinOp::Lt => t(a < b),
        BinOp::Le => t(a <= b),
        BinOp::And => t(a != 0.0 && b != 0.0),
        BinOp::Or => t(a != 0.0 || b != 0.0),
        BinOp::Xor => t((a != 0.0) != (b != 0.0)),
    })
}
