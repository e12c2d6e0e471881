//! The `.npy` container, read by hand: a magic string, a version, a header length, a Python
//! dict literal (`{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }`) and the raw
//! array bytes. Parsing it here rather than through a general reader means every size the
//! file declares (the header length, the shape) is checked against the bytes actually present
//! before anything is sized from it, and trailing bytes are an error rather than ignored.

/// What the header of an `.npy` file declares, and where its data starts.
#[derive(Debug, PartialEq)]
pub(super) struct Header {
    /// The dtype as the file writes it (`<f4`), or the literal text of a structured dtype.
    pub descr: String,
    /// Whether the data is in Fortran (column-major) order.
    pub fortran_order: bool,
    /// The array's dimensions.
    pub shape: Vec<u64>,
    /// Byte offset of the first data byte.
    pub data_start: usize,
}

/// Longest header accepted. numpy itself refuses headers over 10,000 bytes by default; this
/// leaves room for long structured dtypes and keeps parsing time bounded.
pub(super) const MAX_HEADER: usize = 1 << 16;

/// Most nesting of tuples and lists in the header (structured dtypes nest; nothing real nests
/// deeper than a few levels).
const MAX_DEPTH: usize = 16;

/// Parses the magic, version and header of `bytes`; the error says what is wrong.
pub(super) fn parse_header(bytes: &[u8]) -> Result<Header, String> {
    let rest = bytes
        .strip_prefix(b"\x93NUMPY")
        .ok_or("the file does not start with the .npy magic string")?;
    let (&major, rest) = rest.split_first().ok_or("truncated before the version")?;
    let rest = rest.get(1..).ok_or("truncated before the version")?;
    let (len, prefix) = match major {
        1 => {
            let b = rest.get(..2).ok_or("truncated header length")?;
            (u16::from_le_bytes([b[0], b[1]]) as usize, 10)
        }
        2 | 3 => {
            let b = rest.get(..4).ok_or("truncated header length")?;
            (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize, 12)
        }
        v => return Err(format!("unsupported .npy version {v} (expected 1, 2 or 3)")),
    };
    let available = bytes.len() - prefix.min(bytes.len());
    if len > available {
        return Err(format!(
            "the header length field is {len} bytes, but only {available} bytes follow it"
        ));
    }
    if len > MAX_HEADER {
        return Err(format!(
            "the header is {len} bytes long (at most {MAX_HEADER} are accepted)"
        ));
    }
    let text = std::str::from_utf8(&bytes[prefix..prefix + len])
        .map_err(|_| "the header is not UTF-8 text".to_string())?;
    let dict = match Parser::new(text).document()? {
        Value::Dict(d) => d,
        _ => return Err("the header is not a dict".into()),
    };
    let get = |key: &str| {
        dict.iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v)
            .ok_or(format!("the header has no '{key}'"))
    };
    let descr = match get("descr")? {
        Value::Str(s) => s.clone(),
        other => other.to_string(),
    };
    let fortran_order = match get("fortran_order")? {
        Value::Bool(b) => *b,
        other => return Err(format!("'fortran_order' is {other}, not True or False")),
    };
    let shape = match get("shape")? {
        Value::Tuple(items) => items
            .iter()
            .map(|v| match v {
                Value::Int(n) => Ok(*n),
                other => Err(format!("'shape' has {other}, not a non-negative integer")),
            })
            .collect::<Result<_, _>>()?,
        other => return Err(format!("'shape' is {other}, not a tuple")),
    };
    Ok(Header {
        descr,
        fortran_order,
        shape,
        data_start: prefix + len,
    })
}

/// A value of the header's Python literal subset.
#[derive(Debug, PartialEq)]
enum Value {
    Str(String),
    Int(u64),
    Bool(bool),
    Tuple(Vec<Value>),
    List(Vec<Value>),
    Dict(Vec<(String, Value)>),
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let seq = |f: &mut std::fmt::Formatter<'_>, items: &[Value], open, close| {
            write!(f, "{open}")?;
            for (i, v) in items.iter().enumerate() {
                write!(f, "{}{v}", if i > 0 { ", " } else { "" })?;
            }
            write!(f, "{close}")
        };
        match self {
            Value::Str(s) => write!(f, "'{s}'"),
            Value::Int(n) => write!(f, "{n}"),
            Value::Bool(b) => write!(f, "{}", if *b { "True" } else { "False" }),
            // Python writes a one-element tuple with a trailing comma.
            Value::Tuple(items) if items.len() == 1 => seq(f, items, "(", ",)"),
            Value::Tuple(items) => seq(f, items, "(", ")"),
            Value::List(items) => seq(f, items, "[", "]"),
            Value::Dict(items) => {
                write!(f, "{{")?;
                for (i, (k, v)) in items.iter().enumerate() {
                    write!(f, "{}'{k}': {v}", if i > 0 { ", " } else { "" })?;
                }
                write!(f, "}}")
            }
        }
    }
}

/// A recursive-descent reader of the header literal.
struct Parser<'a> {
    text: &'a str,
    at: usize,
}

impl<'a> Parser<'a> {
    fn new(text: &'a str) -> Self {
        Self { text, at: 0 }
    }

    /// The whole header: one value, then only whitespace (numpy pads with spaces and a newline).
    fn document(&mut self) -> Result<Value, String> {
        let v = self.value(0)?;
        self.skip_space();
        if self.at < self.text.len() {
            return Err(format!(
                "unexpected text after the header dict at byte {}",
                self.at
            ));
        }
        Ok(v)
    }

    fn skip_space(&mut self) {
        let rest = &self.text[self.at..];
        self.at += rest.len() - rest.trim_start().len();
    }

    fn peek(&mut self) -> Option<char> {
        self.skip_space();
        self.text[self.at..].chars().next()
    }

    fn expect(&mut self, c: char) -> Result<(), String> {
        if self.peek() == Some(c) {
            self.at += c.len_utf8();
            Ok(())
        } else {
            Err(format!("expected '{c}' at byte {} of the header", self.at))
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, String> {
        if depth > MAX_DEPTH {
            return Err(format!("the header nests deeper than {MAX_DEPTH} levels"));
        }
        match self.peek() {
            Some('{') => {
                let items = self.sequence('{', '}', |p| {
                    let key = match p.value(depth + 1)? {
                        Value::Str(s) => s,
                        other => return Err(format!("dict key {other} is not a string")),
                    };
                    p.expect(':')?;
                    Ok((key, p.value(depth + 1)?))
                })?;
                Ok(Value::Dict(items))
            }
            Some('(') => Ok(Value::Tuple(
                self.sequence('(', ')', |p| p.value(depth + 1))?,
            )),
            Some('[') => Ok(Value::List(
                self.sequence('[', ']', |p| p.value(depth + 1))?,
            )),
            Some(q @ ('\'' | '"')) => {
                let start = self.at + 1;
                let len = self.text[start..]
                    .find(q)
                    .ok_or("unterminated string in the header")?;
                self.at = start + len + 1;
                Ok(Value::Str(self.text[start..start + len].to_string()))
            }
            Some(c) if c.is_ascii_alphanumeric() => {
                let rest = &self.text[self.at..];
                let len = rest
                    .find(|c: char| !c.is_ascii_alphanumeric())
                    .unwrap_or(rest.len());
                let word = &rest[..len];
                self.at += len;
                match word {
                    "True" => Ok(Value::Bool(true)),
                    "False" => Ok(Value::Bool(false)),
                    _ => word
                        .parse()
                        .map(Value::Int)
                        .map_err(|_| format!("'{word}' in the header is not a value")),
                }
            }
            _ => Err(format!(
                "expected a value at byte {} of the header",
                self.at
            )),
        }
    }

    /// Comma-separated items between `open` and `close`; a trailing comma is allowed.
    fn sequence<T>(
        &mut self,
        open: char,
        close: char,
        mut item: impl FnMut(&mut Self) -> Result<T, String>,
    ) -> Result<Vec<T>, String> {
        self.expect(open)?;
        let mut items = Vec::new();
        loop {
            if self.peek() == Some(close) {
                self.at += 1;
                return Ok(items);
            }
            items.push(item(self)?);
            match self.peek() {
                Some(',') => self.at += 1,
                Some(c) if c == close => {}
                _ => return Err(format!("expected ',' or '{close}' at byte {}", self.at)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(version: u8, header: &str) -> Vec<u8> {
        let mut b = b"\x93NUMPY".to_vec();
        b.extend([version, 0]);
        if version == 1 {
            b.extend((header.len() as u16).to_le_bytes());
        } else {
            b.extend((header.len() as u32).to_le_bytes());
        }
        b.extend(header.as_bytes());
        b
    }

    #[test]
    fn reads_numpy_headers_of_every_version() {
        let h = "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }   \n";
        for v in [1, 2, 3] {
            let parsed = parse_header(&file(v, h)).unwrap();
            assert_eq!(parsed.descr, "<f4");
            assert!(!parsed.fortran_order);
            assert_eq!(parsed.shape, [3, 8]);
            assert_eq!(parsed.data_start, if v == 1 { 10 } else { 12 } + h.len());
        }
        let one = parse_header(&file(
            1,
            "{'descr':'<f8','fortran_order':True,'shape':(5,)}",
        ));
        assert_eq!(one.unwrap().shape, [5]);
        let structured =
            "{'descr': [('a', '<f4'), ('b', '<i4', (2,))], 'fortran_order': False, 'shape': (1,)}";
        assert_eq!(
            parse_header(&file(1, structured)).unwrap().descr,
            "[('a', '<f4'), ('b', '<i4', (2,))]"
        );
    }

    #[test]
    fn refuses_declared_sizes_beyond_the_file() {
        let mut bomb = b"\x93NUMPY\x02\x00".to_vec();
        bomb.extend(u32::MAX.to_le_bytes());
        bomb.extend(b"{}");
        assert!(
            parse_header(&bomb)
                .unwrap_err()
                .contains("only 2 bytes follow")
        );
        for bad in [
            &b"\x93NUMPY"[..],
            b"\x93NUMPY\x01",
            b"\x93NUMPY\x01\x00\x05",
            b"NUMPY",
        ] {
            assert!(parse_header(bad).is_err(), "{bad:?}");
        }
        let deep = format!("{}{}", "(".repeat(100), ")".repeat(100));
        assert!(parse_header(&file(1, &deep)).unwrap_err().contains("nests"));
        assert!(parse_header(&file(1, "{'descr': '<f4'")).is_err());
        assert!(parse_header(&file(1, "{'descr': '<f4', 'shape': (1,)} x")).is_err());
    }
}
