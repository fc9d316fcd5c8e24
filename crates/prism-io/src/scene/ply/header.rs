//! The PLY header: the format line and the elements with their typed properties, read line
//! by line up to `end_header`. Every error names its line and column.

/// How the body is encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// The scalar types of PLY, under their old and their sized names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
    Char,
    UChar,
    Short,
    UShort,
    Int,
    UInt,
    Float,
    Double,
}

impl Scalar {
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::Char,
            "uchar" | "uint8" => Scalar::UChar,
            "short" | "int16" => Scalar::Short,
            "ushort" | "uint16" => Scalar::UShort,
            "int" | "int32" => Scalar::Int,
            "uint" | "uint32" => Scalar::UInt,
            "float" | "float32" => Scalar::Float,
            "double" | "float64" => Scalar::Double,
            _ => return None,
        })
    }

    /// Bytes in the binary formats.
    pub(super) fn size(self) -> usize {
        match self {
            Scalar::Char | Scalar::UChar => 1,
            Scalar::Short | Scalar::UShort => 2,
            Scalar::Int | Scalar::UInt | Scalar::Float => 4,
            Scalar::Double => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::Float | Scalar::Double)
    }

    /// The range of an integer type (every one fits an f64 exactly).
    pub(super) fn integer_range(self) -> (i64, i64) {
        match self {
            Scalar::Char => (i8::MIN.into(), i8::MAX.into()),
            Scalar::UChar => (0, u8::MAX.into()),
            Scalar::Short => (i16::MIN.into(), i16::MAX.into()),
            Scalar::UShort => (0, u16::MAX.into()),
            Scalar::Int => (i32::MIN.into(), i32::MAX.into()),
            Scalar::UInt => (0, u32::MAX.into()),
            Scalar::Float | Scalar::Double => (i64::MIN, i64::MAX),
        }
    }

    pub(super) fn name(self) -> &'static str {
        match self {
            Scalar::Char => "char",
            Scalar::UChar => "uchar",
            Scalar::Short => "short",
            Scalar::UShort => "ushort",
            Scalar::Int => "int",
            Scalar::UInt => "uint",
            Scalar::Float => "float",
            Scalar::Double => "double",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PropertyType {
    Scalar(Scalar),
    /// A count of type `count`, then that many values of type `item`.
    List {
        count: Scalar,
        item: Scalar,
    },
}

#[derive(Clone, Debug)]
pub(super) struct Property {
    pub name: String,
    pub ty: PropertyType,
    /// Where it is declared, for errors about it.
    pub line: usize,
}

#[derive(Clone, Debug)]
pub(super) struct Element {
    pub name: String,
    pub count: usize,
    pub properties: Vec<Property>,
    pub line: usize,
    /// Column of the count in the `element` line.
    pub count_column: usize,
}

impl Element {
    /// Bytes one instance needs at least in a binary body (every list empty).
    pub(super) fn min_binary_size(&self) -> usize {
        self.properties
            .iter()
            .map(|p| match p.ty {
                PropertyType::Scalar(s) => s.size(),
                PropertyType::List { count, .. } => count.size(),
            })
            .sum()
    }
}

#[derive(Clone, Debug)]
pub(super) struct Header {
    pub format: Format,
    pub elements: Vec<Element>,
    /// Byte offset of the body.
    pub body_start: usize,
    /// Line number of the body's first line (for ASCII bodies).
    pub body_line: usize,
}

/// A header problem at a line and column.
#[derive(Debug)]
pub(super) struct HeaderError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

/// Reads the header at the start of `bytes`.
pub(super) fn parse(bytes: &[u8]) -> Result<Header, HeaderError> {
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut pos = 0;
    let mut line_number = 0;
    loop {
        line_number += 1;
        if bytes.is_empty() {
            return Err(HeaderError {
                line: 1,
                column: 1,
                message: "expected 'ply' on the first line; the file is empty".into(),
            });
        }
        if pos >= bytes.len() {
            return Err(HeaderError {
                line: line_number.max(2) - 1,
                column: 1,
                message: "the file ends inside the header; expected end_header".into(),
            });
        }
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |i| pos + i);
        let raw = &bytes[pos..end];
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        pos = (end + 1).min(bytes.len());
        let text = String::from_utf8_lossy(raw);
        let words = words(&text);
        let error = |word: usize, message: String| HeaderError {
            line: line_number,
            column: words.get(word).map_or(text.chars().count() + 1, |w| w.0),
            message,
        };

        if line_number == 1 {
            if text.trim() != "ply" {
                return Err(HeaderError {
                    line: 1,
                    column: 1,
                    message: "expected 'ply' on the first line: this is not a PLY file".into(),
                });
            }
            continue;
        }
        let Some(&(_, keyword)) = words.first() else {
            return Err(error(
                0,
                "expected a header statement, found an empty line".into(),
            ));
        };
        match keyword {
            "comment" | "obj_info" => {}
            "format" => {
                if format.is_some() || !elements.is_empty() {
                    return Err(error(
                        0,
                        "the format line must come once, before the elements".into(),
                    ));
                }
                format = Some(match words.get(1).map(|w| w.1) {
                    Some("ascii") => Format::Ascii,
                    Some("binary_little_endian") => Format::BinaryLittleEndian,
                    Some("binary_big_endian") => Format::BinaryBigEndian,
                    other => {
                        return Err(error(
                            1,
                            format!(
                                "expected ascii, binary_little_endian or binary_big_endian; \
                                 found '{}'",
                                other.unwrap_or("")
                            ),
                        ))
                    }
                });
                match words.get(2).map(|w| w.1) {
                    Some("1.0") if words.len() == 3 => {}
                    _ => return Err(error(2, "expected the version 1.0 after the format".into())),
                }
            }
            "element" => {
                let (Some(&(_, name)), Some(&(count_column, count))) = (words.get(1), words.get(2))
                else {
                    return Err(error(words.len(), "expected 'element NAME COUNT'".into()));
                };
                if words.len() > 3 {
                    return Err(error(
                        3,
                        "expected 'element NAME COUNT' and nothing more".into(),
                    ));
                }
                let count: usize = count.parse().map_err(|_| {
                    error(
                        2,
                        format!("expected the element count, a whole number ≥ 0; found '{count}'"),
                    )
                })?;
                if elements.iter().any(|e| e.name == name) {
                    return Err(error(1, format!("a second element '{name}'")));
                }
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                    line: line_number,
                    count_column,
                });
            }
            "property" => {
                let property = property(&words).map_err(|(word, message)| error(word, message))?;
                let Some(element) = elements.last_mut() else {
                    return Err(error(0, "a property before any element".into()));
                };
                if element.properties.iter().any(|p| p.name == property.0) {
                    return Err(error(
                        words.len() - 1,
                        format!(
                            "element '{}' has a second property '{}'",
                            element.name, property.0
                        ),
                    ));
                }
                element.properties.push(Property {
                    name: property.0,
                    ty: property.1,
                    line: line_number,
                });
            }
            "end_header" => {
                let Some(format) = format else {
                    return Err(error(
                        0,
                        "the header has no format line; expected 'format ascii 1.0' (or \
                         binary_little_endian, binary_big_endian) after 'ply'"
                            .into(),
                    ));
                };
                return Ok(Header {
                    format,
                    elements,
                    body_start: pos,
                    body_line: line_number + 1,
                });
            }
            other => {
                return Err(error(
                    0,
                    format!(
                        "unknown header statement '{other}'; expected format, element, property, \
                         comment, obj_info or end_header"
                    ),
                ))
            }
        }
    }
}

/// Words of a line with their 1-based columns.
fn words(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut column = 0;
    let mut start = None;
    for (i, c) in text.char_indices() {
        column += 1;
        match (c.is_whitespace(), start) {
            (false, None) => start = Some((i, column)),
            (true, Some((s, col))) => {
                out.push((col, &text[s..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some((s, col)) = start {
        out.push((col, &text[s..]));
    }
    out
}

/// `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`; errors name a word.
fn property(words: &[(usize, &str)]) -> Result<(String, PropertyType), (usize, String)> {
    let scalar = |i: usize| -> Result<Scalar, (usize, String)> {
        let name = words.get(i).map_or("", |w| w.1);
        Scalar::from_name(name).ok_or_else(|| {
            (
                i,
                format!(
                    "expected a property type (char, uchar, short, ushort, int, uint, float, \
                     double or int8 … float64); found '{name}'"
                ),
            )
        })
    };
    let (ty, name_at) = if words.get(1).map(|w| w.1) == Some("list") {
        let count = scalar(2)?;
        if !count.is_integer() {
            return Err((
                2,
                format!(
                    "a list's count must be an integer type, not {}",
                    count.name()
                ),
            ));
        }
        (
            PropertyType::List {
                count,
                item: scalar(3)?,
            },
            4,
        )
    } else {
        (PropertyType::Scalar(scalar(1)?), 2)
    };
    match (words.get(name_at), words.len()) {
        (Some(&(_, name)), n) if n == name_at + 1 => Ok((name.to_string(), ty)),
        (None, _) => Err((
            name_at,
            "expected the property's name after its type".into(),
        )),
        _ => Err((
            name_at + 1,
            "expected nothing after the property's name".into(),
        )),
    }
}
