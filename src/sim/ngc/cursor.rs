//! The general line reader: a cursor over one line that reads words, numbers, parameter
//! references, bracketed expressions and comments.

use super::*;

pub(super) struct Cursor<'a> {
    /// Significant characters (lower-cased, no blanks) with their 1-based columns.
    pub(super) c: &'a [(char, usize)],
    pub(super) i: usize,
    pub(super) depth: usize,
}

impl Cursor<'_> {
    pub(super) fn peek(&self) -> Option<char> {
        self.c.get(self.i).map(|x| x.0)
    }
    pub(super) fn col(&self) -> usize {
        self.c
            .get(self.i)
            .or(self.c.last())
            .map(|x| x.1)
            .unwrap_or(1)
    }
    pub(super) fn eat(&mut self, ch: char) -> bool {
        if self.peek() == Some(ch) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    pub(super) fn starts_with(&self, s: &str) -> bool {
        let mut k = self.i;
        for ch in s.chars() {
            match self.c.get(k) {
                Some(&(x, _)) if x == ch => k += 1,
                _ => return false,
            }
        }
        true
    }
    pub(super) fn err<T>(&self, msg: impl Into<String>) -> Result<T, (usize, String)> {
        Err((self.col(), msg.into()))
    }

    /// One level deeper, an error past [`MAX_NESTING`]; [`Cursor::leave`] undoes it.
    pub(super) fn enter(&mut self) -> Result<(), (usize, String)> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return self.err(format!(
                "expression nested deeper than {MAX_NESTING} levels (brackets, unary signs \
                 and # indirections count)"
            ));
        }
        Ok(())
    }

    pub(super) fn leave(&mut self) {
        self.depth -= 1;
    }

    /// A real value: number, parameter, `[expr]`, function, with optional unary sign.
    pub(super) fn real_value(&mut self) -> Result<Expr, (usize, String)> {
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

    pub(super) fn number(&mut self) -> Result<Expr, (usize, String)> {
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

    pub(super) fn param_ref(&mut self) -> Result<ParamRef, (usize, String)> {
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

    pub(super) fn bracketed(&mut self) -> Result<Expr, (usize, String)> {
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
    pub(super) fn expression(&mut self) -> Result<Expr, (usize, String)> {
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

    pub(super) fn binop(&mut self) -> Result<BinOp, (usize, String)> {
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

    pub(super) fn function(&mut self) -> Result<Expr, (usize, String)> {
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
pub(super) fn reduce(values: &mut Vec<Expr>, ops: &mut Vec<BinOp>) {
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
