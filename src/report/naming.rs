//! Naming rows of a list (spectra, compared pairs, maps) by what tells them apart: the words
//! every row has are said once, each row keeps its own words with the fastest-changing
//! parameter first, so rows that differ only in their last parameter differ in their first
//! characters. Used by `rocklab compare` and the workbench alike.

/// One word of a label: `kθ=3` (parameter `kθ`), a device's or record's name (keyed by its
/// place: the first word, the word after ` · `).
#[derive(Clone, Debug, PartialEq)]
struct Word<'a> {
    key: String,
    text: &'a str,
}

fn words(label: &str) -> Vec<Word<'_>> {
    let mut out = Vec::new();
    let mut after_dot = false;
    for (i, w) in label.split(' ').filter(|w| !w.is_empty()).enumerate() {
        if w == "·" {
            after_dot = true;
            continue;
        }
        let key = match w.split_once('=') {
            Some((k, _)) => k.to_string(),
            None if after_dot => "·record".into(),
            None if i == 0 => "·device".into(),
            None => format!("·{i}"),
        };
        out.push(Word { key, text: w });
    }
    out
}

/// Labels split into what all share and what each has of its own.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Names {
    /// The words every label has, in the first label's order (empty for a single label).
    pub shared: String,
    /// Each label's own words, fastest-changing parameter first (the whole label where it has
    /// nothing of its own).
    pub names: Vec<String>,
}

/// Split `labels` into shared words and each label's own ([`Names`]).
pub fn distinguish(labels: &[&str]) -> Names {
    let all: Vec<Vec<Word>> = labels.iter().map(|l| words(l)).collect();
    if all.len() < 2 {
        return Names {
            shared: String::new(),
            names: labels.iter().map(|l| l.to_string()).collect(),
        };
    }
    let shared: Vec<&Word> = all[0]
        .iter()
        .filter(|w| all.iter().all(|ws| ws.contains(w)))
        .collect();
    // How often a parameter changes from one row to the next: the innermost loop of a grid
    // changes at every row.
    let value = |ws: &[Word<'_>], key: &str| -> Option<String> {
        ws.iter().find(|w| w.key == key).map(|w| w.text.to_string())
    };
    let changes = |key: &str| {
        all.windows(2)
            .filter(|p| value(&p[0], key) != value(&p[1], key))
            .count()
    };
    let names = all
        .iter()
        .zip(labels)
        .map(|(ws, label)| {
            let mut own: Vec<&Word> = ws.iter().filter(|w| !shared.contains(w)).collect();
            if own.is_empty() {
                return label.to_string();
            }
            // The device's name stays first; then the fastest-changing parameter.
            own.sort_by_key(|w| (w.key != "·device", std::cmp::Reverse(changes(&w.key))));
            own.iter().map(|w| w.text).collect::<Vec<_>>().join(" ")
        })
        .collect();
    Names {
        shared: shared.iter().map(|w| w.text).collect::<Vec<_>>().join(" "),
        names,
    }
}

/// Compared pairs named alike: a pair's label is B's own words, then the situation both sides
/// share, then A's own words after `A:`, each part by [`distinguish`]; the words every pair
/// has are said once in `shared` ("A sequential · B mechanistic σ=0.5 · R=3").
pub fn pair_names(pairs: &[(&str, &str)]) -> Names {
    let split = |a: &str, b: &str| {
        let (wa, wb) = (words(a), words(b));
        let only = |x: &[Word], y: &[Word]| {
            x.iter()
                .filter(|w| !y.contains(w))
                .map(|w| w.text)
                .collect::<Vec<_>>()
                .join(" ")
        };
        let both = wa
            .iter()
            .filter(|w| wb.contains(w))
            .map(|w| w.text)
            .collect::<Vec<_>>()
            .join(" ");
        (only(&wa, &wb), only(&wb, &wa), both)
    };
    let parts: Vec<(String, String, String)> = pairs.iter().map(|(a, b)| split(a, b)).collect();
    let side = |f: &dyn Fn(&(String, String, String)) -> &str| {
        distinguish(&parts.iter().map(f).collect::<Vec<_>>())
    };
    let (a, b, both) = (side(&|p| &p.0), side(&|p| &p.1), side(&|p| &p.2));
    let single = pairs.len() < 2;
    // In a single pair (or a part every pair has alike) the part is shared as a whole.
    let own = |n: &Names, i: usize, whole: &str| -> String {
        if single || (n.shared == whole && !whole.is_empty()) {
            String::new()
        } else {
            n.names[i].clone()
        }
    };
    let names = (0..pairs.len())
        .map(|i| {
            let (pa, pb, ps) = &parts[i];
            let mut text = [own(&b, i, pb), own(&both, i, ps)]
                .into_iter()
                .filter(|s| !s.is_empty())
                .collect::<Vec<_>>()
                .join(" · ");
            let a_own = own(&a, i, pa);
            if !a_own.is_empty() {
                if !text.is_empty() {
                    text.push_str(" · ");
                }
                text.push_str(&format!("A: {a_own}"));
            }
            if text.is_empty() {
                format!("A {pa} · B {pb}")
            } else {
                text
            }
        })
        .collect();
    let shared_of = |n: &Names, i: usize| -> String {
        if single {
            [&parts[0].0, &parts[0].1, &parts[0].2][i].to_string()
        } else {
            n.shared.clone()
        }
    };
    let mut shared = Vec::new();
    for (tag, i, n) in [("A ", 0, &a), ("B ", 1, &b), ("", 2, &both)] {
        let s = shared_of(n, i);
        if !s.is_empty() {
            shared.push(format!("{tag}{s}"));
        }
    }
    Names {
        shared: shared.join(" · "),
        names,
    }
}

/// Legend entries with the parameters every entry shares said once: the shared `name=value`
/// words (joined, empty when none or fewer than two entries) and each label without them, its
/// own words in their order. Device and record names stay in every entry (they name the line);
/// an entry left with nothing keeps its whole label.
pub fn factor_shared(labels: &[String]) -> (String, Vec<String>) {
    let tokens = |l: &str| -> Vec<String> {
        l.split(' ')
            .filter(|w| !w.is_empty())
            .map(str::to_string)
            .collect()
    };
    let all: Vec<Vec<String>> = labels.iter().map(|l| tokens(l)).collect();
    if all.len() < 2 {
        return (String::new(), labels.to_vec());
    }
    let shared: Vec<String> = all[0]
        .iter()
        .filter(|w| w.contains('=') && all.iter().all(|ws| ws.contains(w)))
        .cloned()
        .collect();
    let own = all
        .iter()
        .zip(labels)
        .map(|(ws, label)| {
            let mut kept: Vec<&str> = Vec::new();
            for w in ws.iter().filter(|w| !shared.contains(w)) {
                // A `·` separator only between two kept words.
                if w == "·" && kept.last().is_none_or(|l| *l == "·") {
                    continue;
                }
                kept.push(w);
            }
            while kept.last() == Some(&"·") {
                kept.pop();
            }
            if kept.is_empty() {
                label.clone()
            } else {
                kept.join(" ")
            }
        })
        .collect();
    (shared.join(" "), own)
}

/// `text` in lines of at most `width` characters, broken between words (a word longer than
/// the width gets a line of its own, cut by the terminal rather than lost here).
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let needed = line.chars().count() + usize::from(!line.is_empty()) + word.chars().count();
        if !line.is_empty() && needed > width.max(1) {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_differing_in_their_last_parameter_differ_first() {
        let n = distinguish(&[
            "bare R=1 α=0.1047 A/(g·α)=1.5",
            "bare R=1 α=0.1047 A/(g·α)=2.5",
            "bare R=3 α=0.1047 A/(g·α)=1.5",
            "bare R=3 α=0.1047 A/(g·α)=2.5",
        ]);
        assert_eq!(n.shared, "bare α=0.1047");
        assert_eq!(
            n.names,
            [
                "A/(g·α)=1.5 R=1",
                "A/(g·α)=2.5 R=1",
                "A/(g·α)=1.5 R=3",
                "A/(g·α)=2.5 R=3"
            ]
        );
        // A single row keeps its whole label; records are words too.
        assert_eq!(
            distinguish(&["mechanistic up=0"]).names,
            ["mechanistic up=0"]
        );
        let n = distinguish(&["sequential · landers", "sequential · kobe"]);
        assert_eq!(
            (n.shared.as_str(), n.names),
            ("sequential", vec!["landers".into(), "kobe".into()])
        );
    }

    #[test]
    fn pairs_name_the_grid_member_and_the_situation() {
        let n = pair_names(&[
            ("sequential R=1", "mechanistic kθ=3 ξθ=0.02 R=1"),
            ("sequential R=1", "mechanistic kθ=30 ξθ=0.02 R=1"),
            ("sequential R=3", "mechanistic kθ=3 ξθ=0.02 R=3"),
            ("sequential R=3", "mechanistic kθ=30 ξθ=0.02 R=3"),
        ]);
        assert_eq!(n.shared, "A sequential · B mechanistic ξθ=0.02");
        assert_eq!(
            n.names,
            ["kθ=3 · R=1", "kθ=30 · R=1", "kθ=3 · R=3", "kθ=30 · R=3"]
        );
        // One pair: everything is said once, above.
        let n = pair_names(&[("sequential", "mechanistic kθ=3")]);
        assert_eq!(n.shared, "A sequential · B mechanistic kθ=3");
        // A grid against its own first member.
        let n = pair_names(&[
            ("mechanistic kθ=0.3", "mechanistic kθ=3"),
            ("mechanistic kθ=0.3", "mechanistic kθ=30"),
        ]);
        assert_eq!(n.shared, "A kθ=0.3 · mechanistic");
        assert_eq!(n.names, ["kθ=3", "kθ=30"]);
    }

    #[test]
    fn a_parameter_every_legend_entry_has_is_said_once() {
        let labels: Vec<String> = ["none σ=0.5", "inerter σ=0.5", "mechanistic σ=0.5 kθ=3"]
            .map(String::from)
            .to_vec();
        let (shared, own) = factor_shared(&labels);
        assert_eq!(shared, "σ=0.5");
        assert_eq!(own, ["none", "inerter", "mechanistic kθ=3"]);
        // Nothing shared: unchanged; one entry: unchanged; a device shared stays.
        let labels: Vec<String> = ["bare σ=1", "bare σ=2"].map(String::from).to_vec();
        assert_eq!(factor_shared(&labels), (String::new(), labels.clone()));
        let one = vec!["mechanistic σ=0.5".to_string()];
        assert_eq!(factor_shared(&one), (String::new(), one.clone()));
        let labels: Vec<String> = ["sequential σ=1 · landers", "sequential σ=1 · kobe"]
            .map(String::from)
            .to_vec();
        let (shared, own) = factor_shared(&labels);
        assert_eq!(shared, "σ=1");
        assert_eq!(own, ["sequential · landers", "sequential · kobe"]);
    }

    #[test]
    fn wrapping_keeps_every_word() {
        assert_eq!(
            wrap("kθ=3 ξθ=0.02 fμ=0 up=0.005", 12),
            ["kθ=3 ξθ=0.02", "fμ=0", "up=0.005"]
        );
        assert_eq!(wrap("", 5), [""]);
    }
}
