//! The Part 21 lexer (ISO 10303-21 §5–§7): the DATA section's entity instances, simple or
//! complex, with their parameters (numbers, strings, enumerations, references, lists, typed
//! values, unset), `/* comments */` skipped and the line of each instance kept for errors.

use std::collections::HashMap;

use super::StepError;

/// A parameter value of an entity instance.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// integer or real
    Number(f64),
    /// 'text'
    Text(String),
    /// .ENUM.
    Enum(String),
    /// #N
    Ref(u64),
    /// ( … )
    List(Vec<Value>),
    /// $ or *
    Unset,
    /// TYPE( … ) inside a parameter list
    Typed(String, Vec<Value>),
}

/// One instance: its parts (one for a simple instance, several for a complex one).
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// (entity type, parameters) per part
    pub parts: Vec<(String, Vec<Value>)>,
    /// 1-based line where it starts
    pub line: usize,
}

/// Parses the DATA section of a Part 21 file into its instances.
pub fn parse_instances(text: &str) -> Result<HashMap<u64, Instance>, StepError> {
    let bytes = text.as_bytes();
    let Some(start) = text.find("DATA;") else {
        return Err(StepError::Syntax {
            line: 1,
            detail: "no DATA section (not an ISO 10303-21 file?)".into(),
        });
    };
    let mut p = Parser {
        b: bytes,
        i: start + 5,
        line: 1 + text[..start].matches('\n').count(),
    };
    let mut out = HashMap::new();
    loop {
        p.skip();
        if p.i >= bytes.len() {
            return Err(p.err("the DATA section has no ENDSEC"));
        }
        if bytes[p.i..].starts_with(b"ENDSEC") {
            break;
        }
        if bytes[p.i] != b'#' {
            return Err(p.err("expected an instance #N = …"));
        }
        let line = p.line;
        p.i += 1;
        let id = p.integer()?;
        p.skip();
        p.expect(b'=')?;
        p.skip();
        let mut parts = Vec::new();
        if p.peek() == Some(b'(') {
            // complex instance: ( A(..) B(..) … )
            p.i += 1;
            loop {
                p.skip();
                if p.peek() == Some(b')') {
                    p.i += 1;
                    break;
                }
                let name = p.keyword()?;
                p.skip();
                let args = p.list()?;
                parts.push((name, args));
            }
        } else {
            let name = p.keyword()?;
            p.skip();
            let args = p.list()?;
            parts.push((name, args));
        }
        p.skip();
        p.expect(b';')?;
        if parts.is_empty() {
            return Err(StepError::Syntax {
                line,
                detail: format!("instance #{id} is an empty complex instance"),
            });
        }
        if out.insert(id, Instance { parts, line }).is_some() {
            return Err(StepError::Syntax {
                line,
                detail: format!("instance #{id} is defined twice"),
            });
        }
    }
    Ok(out)
}

struct Parser<'a> {
    b: &'a [u8],
    i: usize,
    line: usize,
}

impl Parser<'_> {
    fn err(&self, detail: &str) -> StepError {
        StepError::Syntax {
            line: self.line,
            detail: detail.to_string(),
        }
    }
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }
    /// Skips white space and /* comments */.
    fn skip(&mut self) {
        while let Some(c) = self.peek() {
            if c == b'\n' {
                self.line += 1;
                self.i += 1;
            } else if c.is_ascii_whitespace() {
                self.i += 1;
            } else if self.b[self.i..].starts_with(b"/*") {
                match self.b[self.i + 2..].windows(2).position(|w| w == b"*/") {
                    Some(k) => {
                        self.line += self.b[self.i..self.i + k + 4]
                            .iter()
                            .filter(|&&c| c == b'\n')
                            .count();
                        self.i += k + 4;
                    }
                    None => self.i = self.b.len(),
                }
            } else {
                break;
            }
        }
    }
    fn expect(&mut self, c: u8) -> Result<(), StepError> {
        if self.peek() == Some(c) {
            self.i += 1;
            Ok(())
        } else {
            Err(self.err(&format!("expected '{}'", c as char)))
        }
    }
    fn integer(&mut self) -> Result<u64, StepError> {
        let s = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        std::str::from_utf8(&self.b[s..self.i])
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| self.err("expected an instance number"))
    }
    fn keyword(&mut self) -> Result<String, StepError> {
        let s = self.i;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'!')
        {
            self.i += 1;
        }
        if s == self.i {
            return Err(self.err("expected an entity name"));
        }
        Ok(String::from_utf8_lossy(&self.b[s..self.i]).to_uppercase())
    }
    /// ( value, value, … )
    fn list(&mut self) -> Result<Vec<Value>, StepError> {
        self.expect(b'(')?;
        let mut out = Vec::new();
        loop {
            self.skip();
            if self.peek() == Some(b')') {
                self.i += 1;
                return Ok(out);
            }
            out.push(self.value()?);
            self.skip();
            match self.peek() {
                Some(b',') => self.i += 1,
                Some(b')') => {}
                _ => return Err(self.err("expected ',' or ')' in a parameter list")),
            }
        }
    }
    fn value(&mut self) -> Result<Value, StepError> {
        match self.peek() {
            Some(b'(') => Ok(Value::List(self.list()?)),
            Some(b'#') => {
                self.i += 1;
                Ok(Value::Ref(self.integer()?))
            }
            Some(b'$') | Some(b'*') => {
                self.i += 1;
                Ok(Value::Unset)
            }
            Some(b'\'') => {
                self.i += 1;
                let mut s = Vec::new();
                loop {
                    match self.peek() {
                        None => return Err(self.err("a string does not end")),
                        Some(b'\'') if self.b.get(self.i + 1) == Some(&b'\'') => {
                            s.push(b'\'');
                            self.i += 2;
                        }
                        Some(b'\'') => {
                            self.i += 1;
                            break;
                        }
                        Some(c) => {
                            if c == b'\n' {
                                self.line += 1;
                            }
                            s.push(c);
                            self.i += 1;
                        }
                    }
                }
                Ok(Value::Text(String::from_utf8_lossy(&s).into_owned()))
            }
            Some(b'.')
                if self
                    .b
                    .get(self.i + 1)
                    .is_some_and(|c| c.is_ascii_alphabetic()) =>
            {
                self.i += 1;
                let s = self.i;
                while self.peek().is_some_and(|c| c != b'.') {
                    self.i += 1;
                }
                let e = String::from_utf8_lossy(&self.b[s..self.i]).to_uppercase();
                self.expect(b'.')?;
                Ok(Value::Enum(e))
            }
            Some(c) if c.is_ascii_digit() || c == b'-' || c == b'+' || c == b'.' => {
                let s = self.i;
                while self
                    .peek()
                    .is_some_and(|c| c.is_ascii_digit() || b"+-.eE".contains(&c))
                {
                    self.i += 1;
                }
                std::str::from_utf8(&self.b[s..self.i])
                    .ok()
                    .and_then(|t| t.parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .map(Value::Number)
                    .ok_or_else(|| self.err("a malformed number"))
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let name = self.keyword()?;
                self.skip();
                Ok(Value::Typed(name, self.list()?))
            }
            _ => Err(self.err("an unexpected character in a parameter list")),
        }
    }
}
