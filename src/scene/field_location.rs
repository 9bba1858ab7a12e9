//! Where a field of a scene file is written: the line and column of `world.colliders[1].friction`
//! in the RON text, so that a value out of range is reported where the user wrote it.

/// 1-based (line, column) of the field at `path` (e.g. `cloth.spacing_m`,
/// `world.colliders[0].friction`, `cloth.lattice_offset_m[1]`) in `text`, if the file writes it
/// (a default value or a `--set` override has no place in the file).
pub fn locate_field(text: &str, path: &str) -> Option<(usize, usize)> {
    let code = blank_comments_and_strings(text);
    let bytes = code.as_bytes();
    // The whole file's top-level struct: from its first '(' to the matching ')'.
    let open = code.find('(')?;
    let (mut start, mut end) = (open + 1, matching(bytes, open)?);
    let mut at = None;
    for segment in path.split('.') {
        let (name, index) = match segment.split_once('[') {
            Some((name, rest)) => (name, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (segment, None),
        };
        let key = find_key(&code[start..end], name)? + start;
        at = Some(key);
        // The value after `name:`.
        let value = key + name.len() + code[key + name.len()..end].find(':')? + 1;
        let value = value + code[value..end].len() - code[value..end].trim_start().len();
        let (vs, ve) = match bytes.get(value) {
            Some(b'(' | b'[') => (value + 1, matching(bytes, value)?),
            // A variant with fields, `Cylinder(radius_m: ..)`: step into its parentheses.
            _ => match code[value..end].find(['(', ',', ')']) {
                Some(k) if bytes[value + k] == b'(' => (value + k + 1, matching(bytes, value + k)?),
                _ => (value, end),
            },
        };
        (start, end) = (vs, ve);
        if let Some(k) = index {
            let element = nth_element(bytes, start, end, k)?;
            at = Some(element);
            (start, end) = match bytes.get(element) {
                Some(b'(') => (element + 1, matching(bytes, element)?),
                _ => (element, end),
            };
        }
    }
    at.map(|offset| line_and_column(text, offset))
}

/// `text` with every comment and string literal's contents replaced by spaces (same length and
/// line breaks), so brackets and keys inside them are not seen.
fn blank_comments_and_strings(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let (mut in_string, mut in_comment) = (false, false);
    while let Some(c) = chars.next() {
        if in_comment {
            if c == '\n' {
                in_comment = false;
                out.push('\n');
            } else {
                out.extend(std::iter::repeat_n(' ', c.len_utf8()));
            }
        } else if in_string {
            if c == '\\' {
                out.push(' ');
                if let Some(next) = chars.next() {
                    out.extend(std::iter::repeat_n(' ', next.len_utf8()));
                }
            } else if c == '"' {
                in_string = false;
                out.push('"');
            } else {
                out.extend(std::iter::repeat_n(' ', c.len_utf8()));
            }
        } else if c == '/' && chars.peek() == Some(&'/') {
            in_comment = true;
            out.push(' ');
        } else if c == '"' {
            in_string = true;
            out.push('"');
        } else {
            out.push(c);
        }
    }
    out
}

/// Index of the bracket closing the one at `open`.
fn matching(bytes: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, b) in bytes.iter().enumerate().skip(open) {
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

/// Offset of `name` written as a key (`name:`) at the top nesting level of `region`.
fn find_key(region: &str, name: &str) -> Option<usize> {
    let bytes = region.as_bytes();
    let mut depth = 0usize;
    let mut k = 0;
    while k < bytes.len() {
        match bytes[k] {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ if depth == 0 && bytes[k..].starts_with(name.as_bytes()) => {
                let before_ok = k == 0 || !(bytes[k - 1].is_ascii_alphanumeric() || bytes[k - 1] == b'_');
                let after = bytes[k + name.len()..].iter().find(|b| !b.is_ascii_whitespace());
                if before_ok && after == Some(&b':') {
                    return Some(k);
                }
            }
            _ => {}
        }
        k += 1;
    }
    None
}

/// Offset of the first character of the `n`-th comma-separated element between `start` and
/// `end` (top level of that region).
fn nth_element(bytes: &[u8], start: usize, end: usize, n: usize) -> Option<usize> {
    let mut depth = 0usize;
    let mut count = 0;
    let mut element_start = None;
    for (k, &b) in bytes.iter().enumerate().take(end).skip(start) {
        if depth == 0 && element_start.is_none() && !b.is_ascii_whitespace() && b != b',' {
            element_start = Some(k);
            if count == n {
                return Some(k);
            }
        }
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b',' if depth == 0 => {
                if element_start.is_some() {
                    count += 1;
                }
                element_start = None;
            }
            _ => {}
        }
    }
    None
}

/// 1-based line and column (in characters) of byte `offset` of `text`.
fn line_and_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "// a comment with colliders: [ and ( in it\n(\n    name: \"a // b\",\n    cloth: (\n        spacing_m: 0.01,\n        lattice_offset_m: (0.001, -0.002),\n    ),\n    world: (\n        colliders: [\n            (name: \"disk\", shape: Cylinder(radius_m: 0.06, half_height_m: 0.02), friction: 0.5),\n            (name: \"floor\", friction: -1.0),\n        ],\n    ),\n    measure: Drape(disk: \"plate\"),\n)\n";

    #[test]
    fn fields_are_found_where_they_are_written() {
        assert_eq!(locate_field(SCENE, "cloth.spacing_m"), Some((5, 9)));
        assert_eq!(locate_field(SCENE, "cloth.lattice_offset_m[1]"), Some((6, 35)));
        assert_eq!(locate_field(SCENE, "world.colliders[1].friction"), Some((11, 29)));
        assert_eq!(locate_field(SCENE, "world.colliders[0].friction"), Some((10, 82)));
        assert_eq!(
            locate_field(SCENE, "world.colliders[0].shape.radius_m"),
            Some((10, 44))
        );
        assert_eq!(locate_field(SCENE, "measure.disk"), Some((14, 20)));
        assert_eq!(locate_field(SCENE, "measure"), Some((14, 5)));
    }

    #[test]
    fn fields_the_file_does_not_write_have_no_place() {
        // Multi-byte characters outside strings do not trip the byte scan.
        assert_eq!(locate_field("(σ: 1, spacing_m: é)", "spacing_m"), Some((1, 8)));
        assert_eq!(locate_field(SCENE, "cloth.perturbation_m"), None);
        assert_eq!(locate_field(SCENE, "world.colliders[2].friction"), None);
        assert_eq!(locate_field(SCENE, "integration.dt_s"), None);
    }
}
