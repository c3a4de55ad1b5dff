//! Shrinking an input that shows a defect, so that the regression test
//! keeps only what matters: lines first, then ever smaller runs of
//! characters (delta debugging), while the defect still shows.

/// The smallest text found (within `budget` tries) for which `fails` still
/// holds; `text` itself if nothing smaller does.
#[must_use]
pub fn minimise(text: &str, fails: &mut dyn FnMut(&str) -> bool, budget: usize) -> String {
    let mut best = text.to_owned();
    let mut tries = 0;
    // Whole lines.
    let mut k = 0;
    loop {
        let lines: Vec<&str> = best.lines().collect();
        if k >= lines.len() || tries >= budget {
            break;
        }
        let candidate = lines
            .iter()
            .enumerate()
            .filter(|&(n, _)| n != k)
            .map(|(_, line)| *line)
            .collect::<Vec<_>>()
            .join("\n");
        tries += 1;
        if fails(&candidate) {
            best = candidate;
        } else {
            k += 1;
        }
    }
    // Runs of characters, halving the run length.
    let mut run = best.chars().count() / 2;
    while run > 0 && tries < budget {
        let mut start = 0;
        loop {
            let chars: Vec<char> = best.chars().collect();
            if start >= chars.len() || tries >= budget {
                break;
            }
            let end = (start + run).min(chars.len());
            let candidate: String = chars[..start].iter().chain(&chars[end..]).collect();
            tries += 1;
            if fails(&candidate) {
                best = candidate;
            } else {
                start += run;
            }
        }
        run /= 2;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::minimise;

    #[test]
    fn keeps_only_what_the_defect_needs() {
        let text = "alpha\nbeta NaN gamma\ndelta";
        let small = minimise(text, &mut |t| t.contains("NaN"), 1000);
        assert_eq!(small, "NaN");
    }
}
