//! The element nesting depth of a URDF, checked before urdf-rs parses it.

/// Deepest element nesting accepted: urdf-rs recurses once per level, so absurdly deep input
/// would overflow the stack (an abort, not an error). A URDF needs 5 levels.
pub(super) const MAX_DEPTH: usize = 64;

/// An upper bound on the element nesting depth of `text` (comments, CDATA sections,
/// processing instructions and declarations skipped; exact on well-formed XML).
pub(super) fn nesting_depth(text: &str) -> usize {
    let b = text.as_bytes();
    let (mut depth, mut max) = (0usize, 0usize);
    let mut i = 0;
    while let Some(k) = b[i..].iter().position(|&c| c == b'<') {
        let lt = i + k;
        let rest = &b[lt..];
        let skip_to = |pattern: &[u8], from: usize| {
            b[from.min(b.len())..]
                .windows(pattern.len())
                .position(|w| w == pattern)
                .map_or(b.len(), |p| from + p + pattern.len())
        };
        i = if rest.starts_with(b"<!--") {
            skip_to(b"-->", lt + 4)
        } else if rest.starts_with(b"<![CDATA[") {
            skip_to(b"]]>", lt + 9)
        } else if rest.starts_with(b"<?") {
            skip_to(b"?>", lt + 2)
        } else if rest.starts_with(b"<!") {
            skip_to(b">", lt + 2)
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            skip_to(b">", lt + 2)
        } else {
            // A start tag: find its end, skipping quoted attribute values.
            let mut quote = None;
            let mut end = b.len();
            for (p, &c) in b.iter().enumerate().skip(lt + 1) {
                match (quote, c) {
                    (Some(q), _) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, b'"' | b'\'') => quote = Some(c),
                    (None, b'>') => {
                        end = p + 1;
                        break;
                    }
                    _ => {}
                }
            }
            let self_closing = end >= 2 && end <= b.len() && b[end - 2] == b'/';
            if !self_closing {
                depth += 1;
                max = max.max(depth);
            } else {
                max = max.max(depth + 1);
            }
            end
        };
        if i >= b.len() {
            break;
        }
    }
    max
}

#[cfg(test)]
mod tests {
    use super::nesting_depth;

    #[test]
    fn nesting_depth_counts_elements_only() {
        let text = r#"<?xml version="1.0"?><!-- <a><b><c> -->
            <robot name="r>"><link name="a"><collision><geometry><box size="1 1 1"/></geometry>
            </collision></link><![CDATA[<x><y>]]></robot>"#;
        assert_eq!(nesting_depth(text), 5);
        assert_eq!(nesting_depth(&"<a>".repeat(1000)), 1000);
    }
}
