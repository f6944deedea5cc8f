//! The instruction VLA evaluations feed the policy, derived from the BDDL file name.

/// LIBERO's `grab_language_from_filename` for a file stem (the name without `.bddl`).
///
/// Evaluations (OpenVLA's `run_libero_eval.py` and the many that copy it) feed the policy this
/// string, not the BDDL `:language` text. Upper-case names (libero_10 / libero_90) drop their
/// `SCENEk_` prefix: 7 characters after `SCENE`, 8 when the name contains `SCENE10`. Underscores
/// become spaces. Upstream quirks are kept: an upper-case name without `SCENE` loses its first six
/// characters (`find` returns -1), and the two-digit rule looks for `SCENE10` anywhere in the name.
pub fn instruction_from_file_name(stem: &str) -> String {
    let chars: Vec<char> = stem.chars().collect();
    let starts_upper = chars.first().is_some_and(|c| c.is_uppercase());
    let text: String = if starts_upper {
        let skip = if stem.contains("SCENE10") { 8 } else { 7 };
        // Python's str.find counts characters and yields -1 when absent.
        let found = find_chars(&chars, "SCENE").map_or(-1, |i| i as isize);
        let start = (found + skip).max(0) as usize;
        chars.iter().skip(start).collect()
    } else {
        stem.to_string()
    };
    text.replace('_', " ")
}

fn find_chars(haystack: &[char], needle: &str) -> Option<usize> {
    let needle: Vec<char> = needle.chars().collect();
    haystack.windows(needle.len()).position(|w| w == needle.as_slice())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lower_case_names_become_the_whole_sentence() {
        assert_eq!(
            instruction_from_file_name("open_the_middle_drawer_of_the_cabinet"),
            "open the middle drawer of the cabinet"
        );
    }

    #[test]
    fn scene_prefixes_are_dropped() {
        assert_eq!(
            instruction_from_file_name("KITCHEN_SCENE3_turn_on_the_stove_and_put_the_moka_pot_on_it"),
            "turn on the stove and put the moka pot on it"
        );
        assert_eq!(
            instruction_from_file_name("LIVING_ROOM_SCENE2_put_both_the_cream_cheese_box_and_the_butter_in_the_basket"),
            "put both the cream cheese box and the butter in the basket"
        );
        assert_eq!(
            instruction_from_file_name("KITCHEN_SCENE10_close_the_top_drawer_of_the_cabinet"),
            "close the top drawer of the cabinet"
        );
    }

    #[test]
    fn upstream_quirks_are_kept() {
        // No SCENE: find() is -1, so 7 - 1 = 6 characters go.
        assert_eq!(instruction_from_file_name("ABCDEFgh_ij"), "gh ij");
        // Shorter than the skip: empty, as Python's slicing gives.
        assert_eq!(instruction_from_file_name("X"), "");
        assert_eq!(instruction_from_file_name(""), "");
    }
}
