//! Mutations of URDF documents for fuzzing the importer: delete, duplicate and swap byte
//! ranges and elements, replace numbers with NaN, infinities, -0, huge or empty values, change
//! joint types, break tags, inject unicode and markup.

use proptest::prelude::*;

/// Replacements for number tokens: special, huge, tiny, empty and malformed values.
const NUMBERS: [&str; 24] = [
    "NaN", "nan", "inf", "-inf", "-0", "1e308", "-1e308", "", "1e-320", "0", "1e400", "0x10",
    "1,5", " ", "999999", "-1e6", "1e7", "3 4", "0.5", "-2", "3.14159", "1e-9", "-0.0", "+1",
];
/// Replacements for `type` attributes, valid and not.
const JOINT_TYPES: [&str; 10] = [
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "floating",
    "planar",
    "spherical",
    "",
    "REVOLUTE",
    "bogus",
];
/// Text injected at random positions: unicode, entities, markup fragments, extra elements.
const INJECTIONS: [&str; 22] = [
    "é",
    "\u{0}",
    "\u{FEFF}",
    "𝔘𝔫𝔦",
    "\u{202E}",
    "&#0;",
    "&#x1F600;",
    "&bogus;",
    "<![CDATA[",
    "<!--",
    "-->",
    "]]>",
    "\"",
    "'",
    "<?xml version=\"1.0\"?>",
    "<!DOCTYPE r [<!ENTITY a \"b\">]>",
    "&amp;",
    "<link name=\"x\"/>",
    "<joint name=\"y\" type=\"fixed\"><parent link=\"x\"/><child link=\"x\"/></joint>",
    "<link name=\"z_handle\"/>",
    "_handle",
    "/..",
];
/// Elements deleted, duplicated and swapped.
const ELEMENTS: [&str; 12] = [
    "link",
    "joint",
    "collision",
    "visual",
    "origin",
    "geometry",
    "limit",
    "axis",
    "mesh",
    "box",
    "parent",
    "child",
];

/// One mutation; positions are fractions of the document length or occurrence indices taken
/// modulo the number of occurrences, so they apply to any document.
#[derive(Debug, Clone)]
pub enum Mutation {
    DeleteBytes(f64, usize),
    DuplicateBytes(f64, usize, f64),
    SwapBytes(f64, f64, usize),
    DeleteElement(usize),
    DuplicateElement(usize),
    SwapElements(usize, usize),
    ReplaceNumber(usize, usize),
    ChangeJointType(usize, usize),
    BreakTag(usize, u8),
    Inject(f64, usize),
}

pub fn mutation() -> impl Strategy<Value = Mutation> {
    let f = 0.0..1.0f64;
    let n = 0usize..10_000;
    // Byte-level mutations mostly break the XML (exercising the parser's error paths);
    // element, number and joint-type mutations mostly keep it well-formed (exercising the tree
    // checks, the limits, the geometry and the builder), so they weigh more.
    prop_oneof![
        1 => (f.clone(), 1usize..64).prop_map(|(a, l)| Mutation::DeleteBytes(a, l)),
        1 => (f.clone(), 1usize..64, f.clone()).prop_map(|(a, l, t)| Mutation::DuplicateBytes(a, l, t)),
        1 => (f.clone(), f.clone(), 1usize..32).prop_map(|(a, b, l)| Mutation::SwapBytes(a, b, l)),
        3 => n.clone().prop_map(Mutation::DeleteElement),
        3 => n.clone().prop_map(Mutation::DuplicateElement),
        3 => (n.clone(), n.clone()).prop_map(|(a, b)| Mutation::SwapElements(a, b)),
        4 => (n.clone(), 0..NUMBERS.len()).prop_map(|(k, r)| Mutation::ReplaceNumber(k, r)),
        2 => (n.clone(), 0..JOINT_TYPES.len()).prop_map(|(k, t)| Mutation::ChangeJointType(k, t)),
        1 => (n, any::<u8>()).prop_map(|(k, how)| Mutation::BreakTag(k, how)),
        1 => (f, 0..INJECTIONS.len()).prop_map(|(a, s)| Mutation::Inject(a, s)),
    ]
}

fn at(doc: &[u8], fraction: f64) -> usize {
    ((doc.len() as f64 * fraction) as usize).min(doc.len())
}

/// Byte ranges of the elements named in `ELEMENTS` (start tag to matching end tag, or the
/// self-closing tag), grouped by name.
fn elements(doc: &[u8]) -> Vec<Vec<(usize, usize)>> {
    let mut all = Vec::new();
    for name in ELEMENTS {
        let mut out = Vec::new();
        let open = format!("<{name}");
        let close = format!("</{name}>");
        let mut i = 0;
        while let Some(k) = find(doc, i, open.as_bytes()) {
            i = k + 1;
            let after = doc.get(k + open.len()).copied().unwrap_or(b'>');
            if !matches!(after, b' ' | b'>' | b'/' | b'\n') {
                continue;
            }
            let Some(gt) = find(doc, k, b">") else {
                continue;
            };
            let end = if doc[gt - 1] == b'/' {
                gt + 1
            } else {
                find(doc, gt, close.as_bytes()).map_or(gt + 1, |c| c + close.len())
            };
            out.push((k, end));
        }
        all.push(out);
    }
    all
}

fn find(doc: &[u8], from: usize, pattern: &[u8]) -> Option<usize> {
    doc.get(from..)?
        .windows(pattern.len())
        .position(|w| w == pattern)
        .map(|k| k + from)
}

/// Byte ranges of number-like tokens (digits with signs, dots and exponents).
fn numbers(doc: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < doc.len() {
        if doc[i].is_ascii_digit()
            || (doc[i] == b'-' && doc.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = i;
            i += 1;
            while i < doc.len()
                && (doc[i].is_ascii_digit() || matches!(doc[i], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

pub fn apply(doc: &mut Vec<u8>, m: &Mutation) {
    let pick = |v: &[(usize, usize)], k: usize| (!v.is_empty()).then(|| v[k % v.len()]);
    match *m {
        Mutation::DeleteBytes(a, l) => {
            let s = at(doc, a);
            doc.drain(s..(s + l).min(doc.len()));
        }
        Mutation::DuplicateBytes(a, l, t) => {
            let s = at(doc, a);
            let bytes = doc[s..(s + l).min(doc.len())].to_vec();
            let t = at(doc, t);
            doc.splice(t..t, bytes);
        }
        Mutation::SwapBytes(a, b, l) => {
            let (a, b) = (at(doc, a).min(at(doc, b)), at(doc, a).max(at(doc, b)));
            let l = l.min(b - a).min(doc.len() - b);
            for k in 0..l {
                doc.swap(a + k, b + k);
            }
        }
        Mutation::DeleteElement(k) => {
            if let Some((s, e)) = pick(&elements(doc).concat(), k) {
                doc.drain(s..e);
            }
        }
        Mutation::DuplicateElement(k) => {
            // The copy goes right after the original, so the XML stays well-formed.
            if let Some((s, e)) = pick(&elements(doc).concat(), k) {
                let bytes = doc[s..e].to_vec();
                doc.splice(e..e, bytes);
            }
        }
        Mutation::SwapElements(a, b) => {
            // Two elements of the same name (two joints, two origins, ...).
            let groups: Vec<Vec<(usize, usize)>> = elements(doc)
                .into_iter()
                .filter(|g| !g.is_empty())
                .collect();
            if !groups.is_empty() {
                let group = &groups[a % groups.len()];
                let (x, y) = (group[a % group.len()], group[b % group.len()]);
                let (x, y) = if x.0 <= y.0 { (x, y) } else { (y, x) };
                if x.1 <= y.0 {
                    let (bx, by) = (doc[x.0..x.1].to_vec(), doc[y.0..y.1].to_vec());
                    doc.splice(y.0..y.1, bx);
                    doc.splice(x.0..x.1, by);
                }
            }
        }
        Mutation::ReplaceNumber(k, r) => {
            if let Some((s, e)) = pick(&numbers(doc), k) {
                doc.splice(s..e, NUMBERS[r].bytes());
            }
        }
        Mutation::ChangeJointType(k, t) => {
            let starts: Vec<(usize, usize)> = (0..doc.len())
                .filter(|&i| doc[i..].starts_with(b"type=\""))
                .filter_map(|i| find(doc, i + 6, b"\"").map(|e| (i + 6, e)))
                .collect();
            if let Some((s, e)) = pick(&starts, k) {
                doc.splice(s..e, JOINT_TYPES[t].bytes());
            }
        }
        Mutation::BreakTag(k, how) => {
            let marks: Vec<(usize, usize)> = (0..doc.len())
                .filter(|&i| matches!(doc[i], b'<' | b'>' | b'/' | b'"'))
                .map(|i| (i, i + 1))
                .collect();
            if let Some((s, e)) = pick(&marks, k) {
                let with: &[u8] = match how % 4 {
                    0 => b"",
                    1 => b"<",
                    2 => b"</x>",
                    _ => b"<<",
                };
                doc.splice(s..e, with.iter().copied());
            }
        }
        Mutation::Inject(a, s) => {
            let t = at(doc, a);
            doc.splice(t..t, INJECTIONS[s].bytes());
        }
    }
}
