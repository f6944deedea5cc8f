//! LIBERO's sampling ranges for articulation init atoms (`(Open x)`, `(Close x)`, `(Turnon x)`,
//! `(Turnoff x)`): each joint the atom names gets a value drawn uniformly from the range of its
//! object class (`articulated_objects.py`'s default open/close/turnon/turnoff ranges). Joints no
//! atom names start at 0, as in LIBERO's files.

use crate::task::Predicate;

/// The uniform range `[low, high]` a joint of `category` is drawn from for `predicate`.
pub fn init_range(category: &str, predicate: Predicate) -> Option<[f64; 2]> {
    use Predicate::*;
    Some(match (category, predicate) {
        ("wooden_cabinet" | "white_cabinet", Open) => [-0.16, -0.14],
        ("wooden_cabinet" | "white_cabinet", Close) => [0.0, 0.005],
        ("microwave", Open) => [-2.094, -1.3],
        ("microwave", Close) => [-0.005, 0.0],
        ("flat_stove", TurnOn) => [0.5, 2.1],
        ("flat_stove", TurnOff) => [-0.005, 0.0],
        _ => return None,
    })
}

/// Whether `predicate` is one of the articulation predicates.
pub fn is_articulation(predicate: Predicate) -> bool {
    matches!(predicate, Predicate::Open | Predicate::Close | Predicate::TurnOn | Predicate::TurnOff)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_sit_inside_the_predicate_thresholds() {
        // Drawers open below −0.14, microwaves below −1.3, knobs turn on at 0.5 rad.
        assert!(init_range("wooden_cabinet", Predicate::Open).unwrap()[1] <= -0.14);
        assert!(init_range("microwave", Predicate::Open).unwrap()[1] <= -1.3);
        assert!(init_range("flat_stove", Predicate::TurnOn).unwrap()[0] >= 0.5);
        assert_eq!(init_range("flat_stove", Predicate::Open), None);
        assert!(is_articulation(Predicate::TurnOff) && !is_articulation(Predicate::On));
    }
}
