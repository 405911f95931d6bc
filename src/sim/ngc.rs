//! RS274NGC block syntax as LinuxCNC reads it: a line becomes words whose values are
//! expressions, parameter assignments, an optional O-word statement and its comments.
//!
//! Following LinuxCNC's reader (manual, "G-code overview": *Format of a line*, *Parameters*,
//! *Expressions*, *Binary operators*, *Functions*): outside comments, spaces and tabs are
//! ignored and letters are case-insensitive (`g 1x [1 + 2 ]` is `G1 X3`); `;` starts a comment
//! to the end of the line; `( )` comments are kept verbatim for `(debug,…)`, `(print,…)`,
//! `(msg,…)` and the `(skinpath:group N)` hook. Values are real numbers, `#` parameters
//! (`#12`, `##1`, `#[1+2]`, `#<name>`, `#<_global>`), bracketed expressions and unary
//! functions (`SIN[30]`, `ATAN[1]/[2]`, `EXISTS[#<x>]`). A top-level `*` followed by digits is
//! a RepRap/Marlin checksum (XOR of the bytes before it).
//!
//! Binary operator precedence, highest first (LinuxCNC `precedence()`): `**`; `*` `/` `MOD`;
//! `+` `-`; `EQ NE GT GE LT LE`; `AND OR XOR`. Operators of equal precedence associate left.

use std::f64::consts::PI;

/// Two values compare equal (EQ/NE) when they differ by less than this: LinuxCNC's
/// `TOLERANCE_EQUAL` (interp_internal.hh).
pub const TOLERANCE_EQUAL: f64 = 0.0001;

/// Highest numbered parameter (LinuxCNC `RS274NGC_MAX_PARAMETERS` − 1).
pub const MAX_PARAMETER: i64 = 5601;

/// Longest line LinuxCNC reads (`LINELEN` − 1).
pub const MAX_LINE_LEN: usize = 255;

/// Deepest nesting accepted in one expression, counting brackets (function arguments
/// included), unary signs and parameter indirections (`#`) alike: `[[1]]`, `--1` and `##1`
/// are each two deep. A guard against stack exhaustion on hostile input (3·10⁴ nested `#`
/// or unary minus signs); LinuxCNC programs nest a handful deep. Flat runs of binary
/// operators do not nest (see [`Expr::Chain`]): a sum of 10⁵ terms is one level.
pub const MAX_NESTING: usize = 64;

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

const FUNCS: [(&str, Func); 12] = [
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

fn func(f: Func, v: f64) -> Result<f64, String> {
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

fn binary(op: BinOp, a: f64, b: f64) -> Result<f64, String> {
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

/// O-word keywords.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OKind {
    /// `sub`: start of a subroutine.
    Sub,
    /// `endsub`
    EndSub,
    /// `call`
    Call,
    /// `return`
    Return,
    /// `if`
    If,
    /// `elseif`
    ElseIf,
    /// `else`
    Else,
    /// `endif`
    EndIf,
    /// `while` (or the end of a `do` loop)
    While,
    /// `endwhile`
    EndWhile,
    /// `do`
    Do,
    /// `repeat`
    Repeat,
    /// `endrepeat`
    EndRepeat,
    /// `break`
    Break,
    /// `continue`
    Continue,
}

const OKINDS: [(&str, OKind); 15] = [
    ("endsub", OKind::EndSub),
    ("endif", OKind::EndIf),
    ("endwhile", OKind::EndWhile),
    ("endrepeat", OKind::EndRepeat),
    ("elseif", OKind::ElseIf),
    ("else", OKind::Else),
    ("sub", OKind::Sub),
    ("call", OKind::Call),
    ("return", OKind::Return),
    ("if", OKind::If),
    ("while", OKind::While),
    ("do", OKind::Do),
    ("repeat", OKind::Repeat),
    ("break", OKind::Break),
    ("continue", OKind::Continue),
];

/// An O-word statement: label (`100` or a lower-case name), keyword and its bracketed
/// arguments (the condition, the repeat count, call arguments or a return value).
#[derive(Clone, Debug, PartialEq)]
pub struct OStmt {
    /// Label: a number as written or a lower-case name.
    pub label: String,
    /// The keyword.
    pub kind: OKind,
    /// Bracketed arguments.
    pub args: Vec<Expr>,
}

/// One word such as `X[#1 + 2]`: upper-case letter, value expression, 1-based column.
#[derive(Clone, Debug, PartialEq)]
pub struct PWord {
    /// Upper-case address letter.
    pub letter: char,
    /// Value expression.
    pub value: Expr,
    /// 1-based column of the letter.
    pub column: usize,
}

/// A syntax problem with its 1-based column and a kebab-case id.
#[derive(Clone, Debug, PartialEq)]
pub struct SyntaxError {
    /// 1-based column.
    pub column: usize,
    /// Kebab-case identifier (`gcode-syntax`, ...).
    pub id: &'static str,
    /// What is wrong.
    pub message: String,
}

/// One parsed line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Line {
    /// A `%` tape mark line.
    pub percent: bool,
    /// Starts with `/` (block delete).
    pub block_delete: bool,
    /// Address words in line order.
    pub words: Vec<PWord>,
    /// `#…=expr` assignments, applied after the block's values are read.
    pub assigns: Vec<(ParamRef, Expr, usize)>,
    /// The O-word statement of the line, if any.
    pub oword: Option<OStmt>,
    /// `( )` comment texts (verbatim, trimmed) and a `;` comment.
    pub comments: Vec<String>,
    /// `$…` GRBL system command text (only at the start of a line).
    pub dollar: Option<String>,
    /// Problems found in the line.
    pub errors: Vec<SyntaxError>,
    /// A checksum was present and correct.
    pub checksum_ok: bool,
}

/// Which constructs the reader accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Syntax {
    /// Parameters, expressions and O-words (LinuxCNC); otherwise they are "not supported".
    pub ngc: bool,
    /// `*NN` checksums (RepRap/Marlin).
    pub checksums: bool,
    /// `$` system commands (GRBL).
    pub dollar: bool,
}

struct Cursor<'a> {
    /// Significant characters (lower-cased, no blanks) with their 1-based columns.
    c: &'a [(char, usize)],
    i: usize,
    depth: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<char> {
        self.c.get(self.i).map(|x| x.0)
    }
    fn col(&self) -> usize {
        self.c
            .get(self.i)
            .or(self.c.last())
            .map(|x| x.1)
            .unwrap_or(1)
    }
    fn eat(&mut self, ch: char) -> bool {
        if self.peek() == Some(ch) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn starts_with(&self, s: &str) -> bool {
        let mut k = self.i;
        for ch in s.chars() {
            match self.c.get(k) {
                Some(&(x, _)) if x == ch => k += 1,
                _ => return false,
            }
        }
        true
    }
    fn err<T>(&self, msg: impl Into<String>) -> Result<T, (usize, String)> {
        Err((self.col(), msg.into()))
    }

    /// One level deeper, an error past [`MAX_NESTING`]; [`Cursor::leave`] undoes it.
    fn enter(&mut self) -> Result<(), (usize, String)> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return self.err(format!(
                "expression nested deeper than {MAX_NESTING} levels (brackets, unary signs \
                 and # indirections count)"
            ));
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.depth -= 1;
    }

    /// A real value: number, parameter, `[expr]`, function, with optional unary sign.
    fn real_value(&mut self) -> Result<Expr, (usize, String)> {
        match self.peek() {
            Some('-') => {
                self.i += 1;
                self.enter()?;
                let v = self.real_value()?;
                self.leave();
                Ok(Expr::Neg(Box::new(v)))
            }
            Some('+') => {
                self.i += 1;
                self.enter()?;
                let v = self.real_value()?;
                self.leave();
                Ok(v)
            }
            Some('[') => self.bracketed(),
            Some('#') => {
                self.i += 1;
                self.enter()?;
                let r = self.param_ref()?;
                self.leave();
                Ok(Expr::Param(r))
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() => self.function(),
            Some(c) => self.err(format!(
                "unexpected character {c:?} where a value should be"
            )),
            None => self.err("a value is missing at the end of the line"),
        }
    }

    fn number(&mut self) -> Result<Expr, (usize, String)> {
        let start = self.i;
        let mut s = String::new();
        let mut points = 0;
        while let Some(c) = self.peek() {
            if c.is_ascii_digit() || (c == '.' && points == 0) {
                points += usize::from(c == '.');
                s.push(c);
                self.i += 1;
            } else {
                break;
            }
        }
        if !s.bytes().any(|b| b.is_ascii_digit()) {
            self.i = start;
            return self.err("a number has no digits");
        }
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Expr::Num(v)),
            _ => self.err(format!("number {s} is out of range")),
        }
    }

    fn param_ref(&mut self) -> Result<ParamRef, (usize, String)> {
        if self.eat('<') {
            let mut name = String::new();
            while let Some(c) = self.peek() {
                self.i += 1;
                if c == '>' {
                    if name.is_empty() {
                        return self.err("empty parameter name #<>");
                    }
                    return Ok(ParamRef::Named(name));
                }
                name.push(c);
            }
            return self.err("named parameter without closing '>'");
        }
        Ok(ParamRef::Num(Box::new(self.real_value()?)))
    }

    fn bracketed(&mut self) -> Result<Expr, (usize, String)> {
        if !self.eat('[') {
            return self.err("'[' expected");
        }
        self.enter()?;
        let e = self.expression()?;
        if !self.eat(']') {
            return self.err("unclosed '[' in expression: ']' expected");
        }
        self.leave();
        Ok(e)
    }

    /// Operator-precedence parse of `value (op value)*` inside brackets.
    fn expression(&mut self) -> Result<Expr, (usize, String)> {
        let mut values = vec![self.real_value()?];
        let mut ops: Vec<BinOp> = Vec::new();
        loop {
            if self.peek() == Some(']') || self.peek().is_none() {
                break;
            }
            let op = self.binop()?;
            while let Some(&top) = ops.last() {
                if top.precedence() >= op.precedence() {
                    reduce(&mut values, &mut ops);
                } else {
                    break;
                }
            }
            ops.push(op);
            values.push(self.real_value()?);
        }
        while !ops.is_empty() {
            reduce(&mut values, &mut ops);
        }
        values
            .pop()
            .map_or_else(|| self.err("empty expression"), Ok)
    }

    fn binop(&mut self) -> Result<BinOp, (usize, String)> {
        const NAMED: [(&str, BinOp); 10] = [
            ("mod", BinOp::Mod),
            ("eq", BinOp::Eq),
            ("ne", BinOp::Ne),
            ("gt", BinOp::Gt),
            ("ge", BinOp::Ge),
            ("lt", BinOp::Lt),
            ("le", BinOp::Le),
            ("and", BinOp::And),
            ("or", BinOp::Or),
            ("xor", BinOp::Xor),
        ];
        if self.starts_with("**") {
            self.i += 2;
            return Ok(BinOp::Pow);
        }
        let single = match self.peek() {
            Some('*') => Some(BinOp::Mul),
            Some('/') => Some(BinOp::Div),
            Some('+') => Some(BinOp::Add),
            Some('-') => Some(BinOp::Sub),
            _ => None,
        };
        if let Some(op) = single {
            self.i += 1;
            return Ok(op);
        }
        for (name, op) in NAMED {
            if self.starts_with(name) {
                self.i += name.len();
                return Ok(op);
            }
        }
        self.err("unknown operator in expression")
    }

    fn function(&mut self) -> Result<Expr, (usize, String)> {
        if self.starts_with("atan") {
            self.i += 4;
            let y = self.bracketed()?;
            if !self.eat('/') {
                return self.err("ATAN needs the form ATAN[y]/[x]");
            }
            let x = self.bracketed()?;
            return Ok(Expr::Atan(Box::new(y), Box::new(x)));
        }
        if self.starts_with("exists") {
            self.i += 6;
            if !(self.eat('[') && self.eat('#') && self.peek() == Some('<')) {
                return self.err("EXISTS needs a named parameter: EXISTS[#<name>]");
            }
            let ParamRef::Named(n) = self.param_ref()? else {
                return self.err("EXISTS needs a named parameter");
            };
            if !self.eat(']') {
                return self.err("unclosed '[' after EXISTS");
            }
            return Ok(Expr::Exists(n));
        }
        for (name, f) in FUNCS {
            if self.starts_with(name) {
                self.i += name.len();
                let arg = self.bracketed()?;
                return Ok(Expr::Func(f, Box::new(arg)));
            }
        }
        self.err("unknown function or a letter where a value should be")
    }
}

/// Applies the top operator to the top two values. A left operand that is already a chain
/// is extended (`(a op₁ b) op₂ c` is the chain of `a` with both), so a left-associative run
/// stays one flat node whatever its length.
fn reduce(values: &mut Vec<Expr>, ops: &mut Vec<BinOp>) {
    if let (Some(op), Some(b), Some(a)) = (ops.pop(), values.pop(), values.pop()) {
        values.push(match a {
            Expr::Chain(first, mut rest) => {
                rest.push((op, b));
                Expr::Chain(first, rest)
            }
            a => Expr::Chain(Box::new(a), vec![(op, b)]),
        });
    }
}

/// Parses one line (without its terminator).
pub fn parse_line(raw: &str, syn: Syntax) -> Line {
    let mut out = Line::default();
    if syn.ngc && raw.len() > MAX_LINE_LEN {
        out.errors.push(SyntaxError {
            column: MAX_LINE_LEN + 1,
            id: "gcode-syntax",
            message: format!(
                "line longer than {MAX_LINE_LEN} characters (LinuxCNC's LINELEN): shorten it"
            ),
        });
    }
    // Split off comments and checksum, collect significant characters.
    let mut sig: Vec<(char, usize)> = Vec::with_capacity(raw.len());
    let mut chars = raw.char_indices().enumerate().peekable();
    let mut first = true;
    while let Some((ci, (bi, c))) = chars.next() {
        let col = ci + 1;
        if c == ' ' || c == '\t' || c == '\r' {
            continue;
        }
        if first {
            first = false;
            if c == '%' {
                out.percent = true;
                continue;
            }
            if c == '/' {
                out.block_delete = true;
                continue;
            }
            if c == '$' && syn.dollar {
                out.dollar = Some(raw[bi + 1..].trim().to_string());
                return out;
            }
        }
        match c {
            ';' => {
                out.comments.push(raw[bi + 1..].trim().to_string());
                break;
            }
            '(' => {
                let mut text = String::new();
                let mut closed = false;
                for (_, (_, ch)) in chars.by_ref() {
                    if ch == ')' {
                        closed = true;
                        break;
                    }
                    text.push(ch);
                }
                if !closed {
                    out.errors.push(SyntaxError {
                        column: col,
                        id: "gcode-syntax",
                        message: "'(' comment not closed".into(),
                    });
                }
                out.comments.push(text.trim().to_string());
            }
            '*' if syn.checksums && depth_zero(&sig) && !next_is_star(raw, bi) => {
                checksum(raw, bi, col, &mut out);
                break;
            }
            _ => sig.push((c.to_ascii_lowercase(), col)),
        }
    }
    if out.percent && !sig.is_empty() {
        // `%` followed by text: LinuxCNC ignores the rest of a percent line.
        sig.clear();
    }
    let mut cur = Cursor {
        c: &sig,
        i: 0,
        depth: 0,
    };
    while let Some(c) = cur.peek() {
        let col = cur.col();
        let res: Result<(), (usize, String)> = if c == '#' {
            if !syn.ngc {
                not_supported(&mut out, col, "parameters (#)");
                break;
            }
            cur.i += 1;
            (|| {
                let p = cur.param_ref()?;
                if !cur.eat('=') {
                    return cur.err("'=' expected after a parameter at the start of a word");
                }
                let v = cur.real_value()?;
                out.assigns.push((p, v, col));
                Ok(())
            })()
        } else if c == 'o' && out.words.is_empty() && out.oword.is_none() && syn.ngc {
            cur.i += 1;
            oword(&mut cur).map(|o| out.oword = Some(o))
        } else if c.is_ascii_alphabetic() || (syn.ngc && (c == '@' || c == '^')) {
            cur.i += 1;
            let letter = c.to_ascii_uppercase();
            if !syn.ngc && matches!(cur.peek(), Some('[') | Some('#')) {
                not_supported(&mut out, col, "expressions and parameters");
                break;
            }
            let flag = !syn.ngc && cur.peek().is_none_or(|n| n.is_ascii_alphabetic());
            if flag {
                // Marlin-style flag word without a value (`M3 I`): taken as 1.
                out.words.push(PWord {
                    letter,
                    value: Expr::Num(1.0),
                    column: col,
                });
                continue;
            }
            cur.real_value().map(|value| {
                out.words.push(PWord {
                    letter,
                    value,
                    column: col,
                })
            })
        } else if c == '[' && !syn.ngc {
            not_supported(&mut out, col, "expressions ([ ])");
            break;
        } else {
            cur.i += 1;
            Err((col, format!("unexpected character {c:?}")))
        };
        if let Err((column, message)) = res {
            out.errors.push(SyntaxError {
                column,
                id: "gcode-syntax",
                message,
            });
            cur.depth = 0;
            // Skip to the next letter to keep going.
            while let Some(ch) = cur.peek() {
                if ch.is_ascii_alphabetic() {
                    break;
                }
                cur.i += 1;
            }
        }
    }
    out
}

/// Longest run of significant characters [`parse_simple`] takes; longer lines are read by
/// the general parser.
const SIMPLE_MAX: usize = 160;

/// Parses one line (without its terminator) into `out`, reusing its buffers: the allocation
/// free path of a streaming reader. Gives the same [`Line`] as [`parse_line`] up to the form
/// of constant values (`X-1` is `Num(-1)` here, `Neg(Num(1))` there; both evaluate alike).
pub fn parse_line_into(raw: &str, syn: Syntax, out: &mut Line) {
    out.percent = false;
    out.block_delete = false;
    out.assigns.clear();
    // Most lines have none: skip the drop glue.
    if out.oword.is_some() {
        out.oword = None;
    }
    out.comments.clear();
    if out.dollar.is_some() {
        out.dollar = None;
    }
    out.errors.clear();
    out.checksum_ok = false;
    // The plain path overwrites the previous line's words in place.
    if parse_plain(raw.as_bytes(), syn, &mut out.words, &mut out.comments) {
        return;
    }
    out.words.clear();
    out.comments.clear();
    if !parse_simple(raw.as_bytes(), syn, out) {
        *out = parse_line(raw, syn);
    }
}

/// Longest line [`parse_plain`] takes (bytes): within [`SIMPLE_MAX`] and [`MAX_LINE_LEN`],
/// so [`parse_simple`] would not refuse it for its length.
const PLAIN_MAX: usize = 128;

/// Most digits [`plain_number`] reads as an integer: 10¹⁵ < 2⁵³, so the digits are exact in
/// an f64.
const PLAIN_DIGITS: usize = 15;

/// Exact powers of ten 10⁰…10²² (every one is an f64 exactly).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The fastest path of [`parse_line_into`]: lines of words `letter [sign] number` separated
/// by blanks or nothing, each number written without blanks inside it (`G1 Y2`,
/// `G0X1Y2`), with ASCII `( )` comments between words and a `;` comment at the end
/// (`G2 X1 Y2 I0.5 J0 (arc)`), which is what CAM output is made of. Gives exactly what
/// [`parse_simple`] gives (same words, columns, bit-identical values and the same comment
/// texts, trimmed, pushed onto `comments`); returns false, with `words` partly overwritten
/// and `comments` partly filled, for anything else (blanks between a letter and its number,
/// a comment inside a word or left open, other characters, long lines), which
/// [`parse_simple`] or the general parser then read.
///
/// The words go into `words` in place of the ones it holds (the previous line's), which
/// is then cut to this line's: each field is written where it stays, where a pushed word
/// would be built on the stack and copied, and that copy's wide load has to wait for the
/// narrow stores of the value just computed (a store-forwarding stall, measured as 40 % of
/// this function's time).
fn parse_plain(
    raw: &[u8],
    syn: Syntax,
    words: &mut Vec<PWord>,
    comments: &mut Vec<String>,
) -> bool {
    if raw.len() > PLAIN_MAX {
        return false;
    }
    let n = raw.len();
    let mut k = 0usize;
    let mut count = 0usize;
    // Only ASCII lines are `parse_simple`'s, so only ASCII comments are this path's.
    let comment = |text: &[u8]| text.is_ascii().then(|| comment_text(text));
    loop {
        while k < n && matches!(raw[k], b' ' | b'\t' | b'\r') {
            k += 1;
        }
        if k == n {
            words.truncate(count);
            return true;
        }
        let c = raw[k];
        if c == b'(' {
            let Some(e) = memchr::memchr(b')', &raw[k + 1..]) else {
                return false;
            };
            let Some(text) = comment(&raw[k + 1..k + 1 + e]) else {
                return false;
            };
            comments.push(text);
            k += e + 2;
            continue;
        }
        if c == b';' {
            let Some(text) = comment(&raw[k + 1..]) else {
                return false;
            };
            comments.push(text);
            k = n;
            continue;
        }
        if !c.is_ascii_alphabetic() || (syn.ngc && (c == b'o' || c == b'O')) {
            return false;
        }
        let column = k + 1;
        k += 1;
        let Some((v, end)) = plain_number(raw, k) else {
            return false;
        };
        // The number must end at a blank, the next letter, a comment or the end of the line.
        if end < n
            && !matches!(
                raw[end],
                b' ' | b'\t' | b'\r' | b'(' | b';' | b'a'..=b'z' | b'A'..=b'Z'
            )
        {
            return false;
        }
        k = end;
        let letter = char::from(c.to_ascii_uppercase());
        match words.get_mut(count) {
            Some(w) => {
                w.letter = letter;
                // A number over a number needs no drop glue.
                match &mut w.value {
                    Expr::Num(x) => *x = v,
                    e => *e = Expr::Num(v),
                }
                w.column = column;
            }
            None => words.push(PWord {
                letter,
                value: Expr::Num(v),
                column,
            }),
        }
        count += 1;
    }
}

/// Reads `[sign] digits [. digits]` (at least one digit) from `raw[k..]`: its value and the
/// index after it. The value is the correctly rounded f64 of the decimal, as `fast_float2`
/// and `str::parse` give it: up to [`PLAIN_DIGITS`] digits with at most 22 after the point,
/// the digits are an exact integer m < 2⁵³ and 10^f is exact, so m / 10^f is one correctly
/// rounded IEEE division; longer numbers go to `fast_float2`. The sign is applied last
/// (`-0` is −0.0, as in [`parse_simple`]).
fn plain_number(raw: &[u8], mut k: usize) -> Option<(f64, usize)> {
    let neg = match raw.get(k) {
        Some(b'-') => {
            k += 1;
            true
        }
        Some(b'+') => {
            k += 1;
            false
        }
        _ => false,
    };
    let start = k;
    let mut m: u64 = 0;
    let mut digits = 0usize;
    let mut frac = 0usize;
    let mut point = false;
    while let Some(&b) = raw.get(k) {
        if b.is_ascii_digit() {
            m = m.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
            digits += 1;
            frac += usize::from(point);
        } else if b == b'.' && !point {
            point = true;
        } else {
            break;
        }
        k += 1;
    }
    if digits == 0 {
        return None;
    }
    let v = if digits <= PLAIN_DIGITS {
        // frac ≤ digits ≤ 15 < 23.
        m as f64 / POW10[frac]
    } else {
        let v = fast_float2::parse::<f64, _>(&raw[start..k]).ok()?;
        if !v.is_finite() {
            return None;
        }
        v
    };
    Some((if neg { -v } else { v }, k))
}

/// A comment's text as the fast paths keep it: trimmed (`text` is ASCII there).
fn comment_text(text: &[u8]) -> String {
    std::str::from_utf8(text).unwrap_or("").trim().to_string()
}

/// The fast path of [`parse_line_into`], over bytes: plain ASCII lines of words
/// `letter [sign] number` with blanks anywhere and `( )` or `;` comments, which is what
/// CAM output is made of. Numbers are read by `fast_float2` (correctly rounded, as
/// `str::parse`). Returns false, with `out` partly filled, at the first thing it does not
/// take (parameters, expressions, O-words, checksums, `%`, `/`, `$`, flags, errors): the
/// general parser then reads the whole line, so every diagnostic comes from one place.
fn parse_simple(raw: &[u8], syn: Syntax, out: &mut Line) -> bool {
    if (syn.ngc && raw.len() > MAX_LINE_LEN) || !raw.is_ascii() {
        return false;
    }
    // Significant bytes (lower case) and their 1-based columns, comments taken out.
    let mut sig = [0u8; SIMPLE_MAX];
    let mut col = [0u16; SIMPLE_MAX];
    let mut n = 0usize;
    let mut k = 0usize;
    while k < raw.len() {
        let c = raw[k];
        match c {
            b' ' | b'\t' | b'\r' => {}
            b';' => {
                out.comments.push(comment_text(&raw[k + 1..]));
                break;
            }
            b'(' => {
                let Some(e) = memchr::memchr(b')', &raw[k + 1..]) else {
                    return false;
                };
                out.comments.push(comment_text(&raw[k + 1..k + 1 + e]));
                k += e + 2;
                continue;
            }
            b'0'..=b'9' | b'.' | b'+' | b'-' | b'a'..=b'z' | b'A'..=b'Z' => {
                if n == SIMPLE_MAX || k >= usize::from(u16::MAX) {
                    return false;
                }
                sig[n] = c.to_ascii_lowercase();
                col[n] = (k + 1) as u16;
                n += 1;
            }
            _ => return false,
        }
        k += 1;
    }
    let sig = &sig[..n];
    let mut i = 0usize;
    while i < n {
        let c = sig[i];
        if !c.is_ascii_alphabetic() || (c == b'o' && syn.ngc) {
            return false;
        }
        let column = usize::from(col[i]);
        i += 1;
        let neg = match sig.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut point = false;
        while i < n && (sig[i].is_ascii_digit() || (sig[i] == b'.' && !point)) {
            point |= sig[i] == b'.';
            i += 1;
        }
        let text = &sig[start..i];
        if !text.iter().any(u8::is_ascii_digit) {
            return false;
        }
        let Ok(v) = fast_float2::parse::<f64, _>(text) else {
            return false;
        };
        if !v.is_finite() {
            return false;
        }
        out.words.push(PWord {
            letter: char::from(c.to_ascii_uppercase()),
            value: Expr::Num(if neg { -v } else { v }),
            column,
        });
    }
    true
}

fn depth_zero(sig: &[(char, usize)]) -> bool {
    let open = sig.iter().filter(|c| c.0 == '[').count();
    let close = sig.iter().filter(|c| c.0 == ']').count();
    open <= close
}

fn next_is_star(raw: &str, bi: usize) -> bool {
    raw.as_bytes().get(bi + 1) == Some(&b'*')
}

fn not_supported(out: &mut Line, column: usize, what: &str) {
    out.errors.push(SyntaxError {
        column,
        id: "unsupported-code",
        message: format!("{what} not supported in this dialect"),
    });
}

fn checksum(raw: &str, star: usize, column: usize, out: &mut Line) {
    let rest = &raw[star + 1..];
    let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    let trailing = rest[digits.len()..]
        .trim()
        .trim_start_matches(';')
        .chars()
        .next()
        .is_some_and(|_| !rest[digits.len()..].trim().starts_with(';'));
    let found = (!digits.is_empty() && digits.len() <= 9)
        .then(|| digits.parse::<u32>().ok())
        .flatten();
    let Some(found) = found else {
        out.errors.push(SyntaxError {
            column,
            id: "bad-checksum",
            message: "'*' without a checksum".into(),
        });
        return;
    };
    let expected = raw.as_bytes()[..star].iter().fold(0u8, |a, b| a ^ b);
    if u32::from(expected) == found {
        out.checksum_ok = true;
    } else {
        out.errors.push(SyntaxError {
            column,
            id: "bad-checksum",
            message: format!("checksum {found} does not match the line (expected {expected})"),
        });
    }
    if trailing {
        out.errors.push(SyntaxError {
            column: column + 1 + digits.len(),
            id: "gcode-syntax",
            message: "text after the checksum".into(),
        });
    }
}

fn oword(cur: &mut Cursor<'_>) -> Result<OStmt, (usize, String)> {
    let label = if cur.eat('<') {
        let mut name = String::new();
        loop {
            match cur.peek() {
                Some('>') => {
                    cur.i += 1;
                    break;
                }
                Some(c) => {
                    name.push(c);
                    cur.i += 1;
                }
                None => return cur.err("O-word name without closing '>'"),
            }
        }
        name
    } else {
        let mut digits = String::new();
        while let Some(c) = cur.peek().filter(|c| c.is_ascii_digit()) {
            digits.push(c);
            cur.i += 1;
        }
        if digits.is_empty() {
            return cur.err("'O' needs a number or <name>");
        }
        digits.trim_start_matches('0').to_string()
    };
    let Some(kind) = OKINDS
        .iter()
        .find(|(k, _)| cur.starts_with(k))
        .map(|&(k, kind)| {
            cur.i += k.len();
            kind
        })
    else {
        return cur.err(format!(
            "O{label} needs a keyword (sub, endsub, call, return, if, elseif, else, endif, \
             while, endwhile, do, repeat, endrepeat, break, continue)"
        ));
    };
    let mut args = Vec::new();
    while cur.peek() == Some('[') {
        args.push(cur.bracketed()?);
    }
    if let Some(c) = cur.peek() {
        return cur.err(format!("unexpected {c:?} after the O-word statement"));
    }
    Ok(OStmt { label, kind, args })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    struct P(HashMap<String, f64>, HashMap<i64, f64>);
    impl ParamSource for P {
        fn numbered(&self, n: i64) -> f64 {
            self.1.get(&n).copied().unwrap_or(0.0)
        }
        fn named(&self, name: &str) -> Option<f64> {
            self.0.get(name).copied()
        }
    }

    const NGC: Syntax = Syntax {
        ngc: true,
        checksums: true,
        dollar: false,
    };

    fn val(s: &str) -> Result<f64, String> {
        let l = parse_line(&format!("X{s}"), NGC);
        if let Some(e) = l.errors.first() {
            return Err(e.message.clone());
        }
        let p = P(
            [("a".to_string(), 2.0)].into_iter().collect(),
            [(1, 3.0), (3, 7.0)].into_iter().collect(),
        );
        l.words[0].value.eval(&p)
    }

    #[test]
    fn manual_examples() {
        // LinuxCNC manual, "Expressions": [1 + acos[0] - [#3 ** [4.0/2]]] with #3 = 7.
        assert!((val("[1 + acos[0] - [#3 ** [4.0/2]]]").unwrap_or(0.0) - 42.0).abs() < 1e-12);
        // "Binary operators": 2.0 / 3 * 1.5 - 5.5 / 11.0 = 0.5.
        assert!((val("[2.0 / 3 * 1.5 - 5.5 / 11.0]").unwrap_or(0.0) - 0.5).abs() < 1e-12);
        assert_eq!(val("[1 + 2 * 3 ** 2]"), Ok(19.0));
        assert_eq!(val("[2 ** 3 ** 2]"), Ok(64.0));
        assert_eq!(val("[1 LT 2 AND 3 GT 2]"), Ok(1.0));
        assert_eq!(val("[-7 MOD 3]"), Ok(2.0));
        assert_eq!(val("[ATAN[1]/[-1]]"), Ok(135.0));
        assert_eq!(val("##1"), Ok(7.0));
        assert_eq!(val("#<a>"), Ok(2.0));
        assert_eq!(val("[EXISTS[#<a>] + EXISTS[#<b>]]"), Ok(1.0));
        assert_eq!(
            val("[FIX[-1.5] + FUP[1.2] + ROUND[2.5] + ABS[-1]]"),
            Ok(4.0)
        );
        assert!((val("[SIN[30]]").unwrap_or(0.0) - 0.5).abs() < 1e-12);
        assert_eq!(val("[1.00001 EQ 1]"), Ok(1.0));
        assert!(val("[1/0]").is_err_and(|e| e.contains("division by zero")));
        assert!(val("[1+2").is_err_and(|e| e.contains("unclosed")));
        assert!(val("#<nope>").is_err_and(|e| e.contains("not defined")));
        assert!(val("[SQRT[-1]]").is_err());
    }

    #[test]
    fn lines() {
        let l = parse_line("N10 #1 = 5 #<x>=[#1+1] G1 x#1 (debug, hi #1) ; rest", NGC);
        assert!(l.errors.is_empty(), "{:?}", l.errors);
        assert_eq!(l.assigns.len(), 2);
        assert_eq!(l.words.len(), 3);
        assert_eq!(l.comments, vec!["debug, hi #1".to_string(), "rest".into()]);
        let o = parse_line("o<my sub> call [1] [2+3]", NGC);
        let os = o.oword.unwrap_or(OStmt {
            label: String::new(),
            kind: OKind::Do,
            args: vec![],
        });
        assert_eq!(
            (os.label.as_str(), os.kind, os.args.len()),
            ("mysub", OKind::Call, 2)
        );
        let w = parse_line("O0100 WHILE [#1 LT 3]", NGC);
        assert_eq!(
            w.oword.map(|o| (o.label, o.kind)),
            Some(("100".into(), OKind::While))
        );
        let g = parse_line("G1 X#1", Syntax { ngc: false, ..NGC });
        assert_eq!(g.errors[0].id, "unsupported-code");
    }

    /// `Neg(Num(v))` as `Num(-v)`: the one difference in form the fast path may make.
    fn norm(mut l: Line) -> Line {
        for w in &mut l.words {
            if let Expr::Neg(e) = &w.value
                && let Expr::Num(v) = **e
            {
                w.value = Expr::Num(-v);
            }
        }
        l
    }

    const DIALECTS: [Syntax; 3] = [
        NGC,
        Syntax {
            ngc: false,
            checksums: true,
            dollar: false,
        },
        Syntax {
            ngc: false,
            checksums: false,
            dollar: true,
        },
    ];

    #[test]
    fn fast_path_takes_cam_lines() {
        for line in [
            "G1 X-1.5 Y2. Z+.25 F1500",
            "n10 g2 x 1 y 2 i.5 j0 (arc) ; done",
            "G0X1Y2",
            "M3 S1000 (spindle on)",
        ] {
            let mut l = Line::default();
            assert!(parse_simple(line.as_bytes(), NGC, &mut l), "{line}");
            assert_eq!(norm(l), norm(parse_line(line, NGC)), "{line}");
        }
        for line in [
            "#1=2",
            "G1 X[1+2]",
            "o100 sub",
            "%",
            "/G0 X1",
            "G1 X1.2.3",
            "G1 X",
        ] {
            let mut l = Line::default();
            assert!(!parse_simple(line.as_bytes(), NGC, &mut l), "{line}");
        }
    }

    /// The values and columns of a line's words, values as bits (−0.0 is not 0.0).
    fn word_bits(l: &Line) -> Vec<(char, u64, usize)> {
        l.words
            .iter()
            .map(|w| match w.value {
                Expr::Num(v) => (w.letter, v.to_bits(), w.column),
                _ => (w.letter, u64::MAX, w.column),
            })
            .collect()
    }

    #[test]
    fn plain_path_takes_cam_lines_and_leaves_the_rest() {
        for line in [
            "G1 X-1.5 Y2. Z+.25 F1500",
            "G0X1Y2",
            "g1 x0.1 y-0 e1.5e3",
            "G1 X1234567.89012345 Y0.30000000000000004",
            "",
            "   \t",
            "M3 S1000 (on)",
            "G1 X1 ; c",
            "G2 X1(a)Y2 ( b  )I0.5;  end ( of ) line ",
            "(only a comment)",
            "G1 X1 ()",
        ] {
            let mut l = Line::default();
            assert!(
                parse_plain(line.as_bytes(), NGC, &mut l.words, &mut l.comments),
                "{line}"
            );
            let mut s = Line::default();
            assert!(parse_simple(line.as_bytes(), NGC, &mut s), "{line}");
            assert_eq!(word_bits(&l), word_bits(&s), "{line}");
            assert_eq!(l.comments, s.comments, "{line}");
        }
        for line in [
            "G1 X 1",
            "G1 X1 2",
            "G1 X(c)1",
            "G1 X1 (open",
            "G1 X1 (é)",
            "G1 X1 ; é",
            "G1 X1.2.3",
            "G1 X",
            "o100 sub",
            "#1=2",
            "G1 X--1",
            "G1 X1é",
        ] {
            let mut l = Line::default();
            assert!(
                !parse_plain(line.as_bytes(), NGC, &mut l.words, &mut l.comments),
                "{line}"
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2048))]
        /// Short decimals read by integer and power of ten are the f64 `str::parse` gives,
        /// bit for bit, across digit counts on both sides of the 15-digit bound.
        #[test]
        fn plain_numbers_are_correctly_rounded(
            int in "[0-9]{0,12}",
            frac in "[0-9]{0,12}",
            point in proptest::bool::ANY,
            sign in "[-+]?",
        ) {
            let text = if point || int.is_empty() {
                format!("{sign}{int}.{frac}")
            } else {
                format!("{sign}{int}")
            };
            let got = plain_number(text.as_bytes(), 0);
            let digits = int.len() + if point || int.is_empty() { frac.len() } else { 0 };
            if digits == 0 {
                proptest::prop_assert!(got.is_none());
            } else {
                let want: f64 = text.parse().map_err(|e| {
                    proptest::test_runner::TestCaseError::fail(format!("{text}: {e}"))
                })?;
                let (v, end) = got.ok_or_else(|| {
                    proptest::test_runner::TestCaseError::fail(text.clone())
                })?;
                proptest::prop_assert_eq!(v.to_bits(), want.to_bits(), "{}", text);
                proptest::prop_assert_eq!(end, text.len());
            }
        }

        /// Where the plain reader takes a line, it gives what the byte fast path gives.
        #[test]
        fn plain_matches_simple(
            line in "([GMXYZFSogx][-+]?[0-9]{0,9}(\\.[0-9]{0,9})?[ \t]{0,2}(\\([a-z ()]{0,5}\\)?)?){0,8}(;[ a-z(]{0,4})?",
            d in 0..3usize,
        ) {
            let syn = DIALECTS[d];
            let mut plain = Line::default();
            if parse_plain(line.as_bytes(), syn, &mut plain.words, &mut plain.comments) {
                let mut simple = Line::default();
                proptest::prop_assert!(parse_simple(line.as_bytes(), syn, &mut simple));
                proptest::prop_assert_eq!(word_bits(&plain), word_bits(&simple));
                proptest::prop_assert_eq!(plain.comments, simple.comments);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// The reused-buffer reader gives what the general parser gives, on lines mixing
        /// words, blanks, comments and stray characters.
        #[test]
        fn parse_line_into_matches_parse_line(
            line in "([GMXYZIJKFSNOgxyoe@#*%/$\\[ \\t]{0,2}[-+]{0,2}[0-9]{0,4}(\\.[0-9]{0,3})?\\.?[ \\t]?(\\([a-z ]{0,4}\\)?)?(;c)?){0,10}",
            d in 0..3usize,
        ) {
            let syn = DIALECTS[d];
            let mut fast = Line::default();
            // Stale content from a previous line must not leak into the next: more words
            // than most lines here, one of them an expression (the plain path overwrites
            // words in place).
            parse_line_into("G1 X[1+#2] Y3 Z4 F5 S6 M7 (old) ; old", syn, &mut fast);
            parse_line_into(&line, syn, &mut fast);
            proptest::prop_assert_eq!(norm(fast), norm(parse_line(&line, syn)));
        }
    }
}
