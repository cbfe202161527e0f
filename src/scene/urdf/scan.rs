//! A lenient pre-scan of the XML text, before urdf-rs parses it.
//!
//! It finds two things urdf-rs does not tell: how deeply elements nest (urdf-rs and its XML
//! back ends recurse once per level, so a document nested thousands of levels deep would
//! overflow the stack, which aborts the process instead of returning an error), and which
//! top-level `<joint>` elements have a `<limit>` child (urdf-rs fills a missing `<limit>` with
//! zeros, indistinguishable from `lower="0" upper="0"`).
//!
//! The scan never fails: it skips comments, CDATA sections, processing instructions and
//! declarations, reads start and end tags with quoted attribute values, and stops at the end
//! of the text. On well-formed XML (the only input urdf-rs accepts) its answers are exact.

/// What the pre-scan found.
#[derive(Debug, Default)]
pub(super) struct Scan {
    /// Deepest element nesting (the root element is at depth 1).
    pub max_depth: usize,
    /// For each child element of the root named `joint`, in document order: whether it has a
    /// child element named `limit`.
    pub joint_has_limit: Vec<bool>,
}

/// Scans `xml` (see the module docs).
pub(super) fn scan(xml: &str) -> Scan {
    let b = xml.as_bytes();
    let mut out = Scan::default();
    let mut depth = 0usize;
    let mut in_joint = false;
    let mut i = 0;
    while let Some(lt) = find_byte(b, i, b'<') {
        let rest = &b[lt..];
        i = if rest.starts_with(b"<!--") {
            skip_past(b, lt + 4, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            skip_past(b, lt + 9, b"]]>")
        } else if rest.starts_with(b"<?") {
            skip_past(b, lt + 2, b"?>")
        } else if rest.starts_with(b"<!") {
            skip_declaration(b, lt + 2)
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            tag_end(b, lt + 2).0
        } else {
            let name_end = (lt + 1..b.len())
                .find(|&k| matches!(b[k], b' ' | b'\t' | b'\r' | b'\n' | b'/' | b'>'))
                .unwrap_or(b.len());
            let name = local_name(&b[lt + 1..name_end]);
            let (end, self_closing) = tag_end(b, name_end);
            let level = depth + 1;
            out.max_depth = out.max_depth.max(level);
            if level == 2 {
                in_joint = name == b"joint";
                if in_joint {
                    out.joint_has_limit.push(false);
                }
            } else if level == 3 && in_joint && name == b"limit" {
                if let Some(last) = out.joint_has_limit.last_mut() {
                    *last = true;
                }
            }
            if !self_closing {
                depth = level;
            }
            end
        };
    }
    out
}

/// The name after a namespace prefix (`x:joint` → `joint`).
fn local_name(name: &[u8]) -> &[u8] {
    match name.iter().rposition(|&c| c == b':') {
        Some(k) => &name[k + 1..],
        None => name,
    }
}

/// Position of the first `c` at or after `from`.
fn find_byte(b: &[u8], from: usize, c: u8) -> Option<usize> {
    b.get(from..)?
        .iter()
        .position(|&x| x == c)
        .map(|k| from + k)
}

/// Position just past the first `pattern` at or after `from` (the end of the text if none).
fn skip_past(b: &[u8], from: usize, pattern: &[u8]) -> usize {
    b.get(from..)
        .and_then(|rest| rest.windows(pattern.len()).position(|w| w == pattern))
        .map_or(b.len(), |k| from + k + pattern.len())
}

/// Position just past a `<!...>` declaration starting at `from`, with a bracketed internal
/// subset and quoted strings skipped.
fn skip_declaration(b: &[u8], from: usize) -> usize {
    let mut brackets = 0usize;
    let mut quote = None;
    for (k, &c) in b.iter().enumerate().skip(from) {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'"' | b'\'') => quote = Some(c),
            (None, b'[') => brackets += 1,
            (None, b']') => brackets = brackets.saturating_sub(1),
            (None, b'>') if brackets == 0 => return k + 1,
            _ => {}
        }
    }
    b.len()
}

/// Position just past the `>` closing a tag whose attributes start at `from`, with quoted
/// attribute values skipped, and whether the tag is self-closing (`/>`).
fn tag_end(b: &[u8], from: usize) -> (usize, bool) {
    let mut quote = None;
    let mut previous = 0u8;
    for (k, &c) in b.iter().enumerate().skip(from) {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'"' | b'\'') => quote = Some(c),
            (None, b'>') => return (k + 1, previous == b'/'),
            _ => {}
        }
        if quote.is_none() && !c.is_ascii_whitespace() {
            previous = c;
        }
    }
    (b.len(), false)
}

#[cfg(test)]
mod tests {
    use super::scan;

    #[test]
    fn finds_limits_and_depth() {
        let s = scan(
            r#"<?xml version="1.0"?><!-- <joint><limit/></joint> -->
            <robot name="r>">
              <link name="a"><collision><geometry><box size="1 1 1"/></geometry></collision></link>
              <joint name="j1" type="revolute"><limit lower="0" upper="1"/></joint>
              <x:joint xmlns:x="u" name="j2"><axis xyz="1 0 0"/></x:joint>
              <joint name="j3"><![CDATA[<limit/>]]><mimic joint="j1"><limit/></mimic></joint>
            </robot>"#,
        );
        assert_eq!(s.joint_has_limit, vec![true, false, false]);
        assert_eq!(s.max_depth, 5);
    }
}
