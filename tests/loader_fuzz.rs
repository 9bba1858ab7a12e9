//! Bad input never panics: thousands of mutated scene and fabric files (characters deleted,
//! inserted or replaced, numbers swapped for extreme, negative or non-finite ones, lines
//! duplicated or cut) are either loaded or rejected with a typed error, and every rejection
//! message names its file.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use kes_cloth::material::Fabric;
use kes_cloth::scene::Scene;
use proptest::prelude::*;

mod common;

const NUMBERS: [&str; 12] = [
    "0", "-0", "-1", "1e308", "-1e308", "1e-320", "NaN", "inf", "-inf", "1e400", "3.5e", "0x10",
];
const CHARS: [char; 14] = [
    '(', ')', ',', ':', '"', '[', ']', '-', 'e', '.', '7', 'x', ' ', 'é',
];

/// One edit, applied at a position given as a fraction of the text length.
#[derive(Clone, Debug)]
enum Edit {
    Delete(f64, usize),
    Insert(f64, usize),
    ReplaceNumber(f64, usize),
    DuplicateLine(f64),
    Truncate(f64),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (0.0..1.0, 1usize..6).prop_map(|(at, n)| Edit::Delete(at, n)),
        (0.0..1.0, 0..CHARS.len()).prop_map(|(at, c)| Edit::Insert(at, c)),
        (0.0..1.0, 0..NUMBERS.len()).prop_map(|(at, k)| Edit::ReplaceNumber(at, k)),
        (0.0..1.0).prop_map(Edit::DuplicateLine),
        (0.0..1.0).prop_map(Edit::Truncate),
    ]
}

fn char_index(text: &str, at: f64) -> usize {
    let chars = text.chars().count();
    let i = ((chars as f64 * at) as usize).min(chars);
    text.char_indices().nth(i).map_or(text.len(), |(b, _)| b)
}

fn apply(text: &str, edit: &Edit) -> String {
    let mut s = text.to_string();
    match *edit {
        Edit::Delete(at, n) => {
            let start = char_index(&s, at);
            let end = s[start..]
                .char_indices()
                .nth(n)
                .map_or(s.len(), |(b, _)| start + b);
            s.replace_range(start..end, "");
        }
        Edit::Insert(at, c) => s.insert(char_index(&s, at), CHARS[c]),
        Edit::ReplaceNumber(at, k) => {
            // The first number at or after the position.
            let from = char_index(&s, at);
            if let Some(off) = s[from..].find(|c: char| c.is_ascii_digit()) {
                let start = from + off;
                let len = s[start..]
                    .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                    .unwrap_or(s.len() - start);
                s.replace_range(start..start + len, NUMBERS[k]);
            }
        }
        Edit::DuplicateLine(at) => {
            let lines: Vec<&str> = s.lines().collect();
            let i = ((lines.len() as f64 * at) as usize).min(lines.len().saturating_sub(1));
            let mut out: Vec<&str> = lines.clone();
            if !lines.is_empty() {
                out.insert(i, lines[i]);
            }
            s = out.join("\n");
        }
        Edit::Truncate(at) => {
            let cut = char_index(&s, at);
            s.truncate(cut);
        }
    }
    s
}

fn shipped(dir: &str) -> Vec<(PathBuf, String)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(common::crate_path(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic(which in 0usize..6, edits in prop::collection::vec(edit(), 1..5)) {
        let scenes = shipped("scenes");
        let (path, text) = &scenes[which % scenes.len()];
        let mutated = edits.iter().fold(text.clone(), |t, e| apply(&t, e));
        let result = catch_unwind(AssertUnwindSafe(|| Scene::from_text(&mutated, path.clone(), &[])));
        prop_assert!(result.is_ok(), "panicked on:\n{mutated}");
        if let Ok(Err(e)) = result {
            prop_assert!(e.to_string().contains(&*path.to_string_lossy()), "no file in: {e}");
        }
    }

    #[test]
    fn mutated_fabrics_never_panic(which in 0usize..4, edits in prop::collection::vec(edit(), 1..5)) {
        let fabrics = shipped("assets/fabrics");
        let (_, text) = &fabrics[which % fabrics.len()];
        let mutated = edits.iter().fold(text.clone(), |t, e| apply(&t, e));
        let path = std::env::temp_dir().join(format!("kes-cloth-fuzz-{}-{which}.ron", std::process::id()));
        std::fs::write(&path, &mutated).unwrap();
        let result = catch_unwind(AssertUnwindSafe(|| Fabric::load(&path)));
        prop_assert!(result.is_ok(), "panicked on:\n{mutated}");
        if let Ok(Err(e)) = result {
            prop_assert!(e.to_string().contains(&*path.to_string_lossy()), "no file in: {e}");
        }
    }
}
