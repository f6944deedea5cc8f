//! How LIBERO orients each movable category at spawn.
//!
//! LIBERO's object classes give a spawn rotation that, through an xyzw/wxyz mix-up, lands in the
//! state as a fixed quaternion per category (constant across all 50 states of every task). The
//! values below are those quaternions as LIBERO's init files show them. The HOPE groceries are
//! modelled lying on their side, so theirs stand the item up; the rest are plain yaws.

use std::f64::consts::FRAC_1_SQRT_2 as H;

use vifo_robots::spatial::{Mat3, Vec3, axis_angle, quat_wxyz};

/// +90° about z.
const YAW_90: [f64; 4] = [H, 0.0, 0.0, H];
/// 180° about z.
const YAW_180: [f64; 4] = [0.0, 0.0, 0.0, 1.0];
/// −90° about z (LIBERO stores it as (−0.7071, 0, 0, 0.7071)).
const YAW_270: [f64; 4] = [-H, 0.0, 0.0, H];
/// Cans: 180° about (0, 1, 1)/√2, standing the can on its base.
const CAN_UPRIGHT: [f64; 4] = [0.0, 0.0, H, H];
/// Bottles and cartons: 120° about (1, 1, 1)/√3, standing them on their base.
const BOTTLE_UPRIGHT: [f64; 4] = [0.5, 0.5, 0.5, 0.5];

/// The spawn orientation (w, x, y, z) of a movable category, `None` for categories LIBERO's
/// files do not show.
pub fn spawn_quat(category: &str) -> Option<[f64; 4]> {
    Some(match category {
        "akita_black_bowl" | "plate" | "glazed_rim_porcelain_ramekin" | "basket" | "chefmate_8_frypan" | "cookies"
        | "bbq_sauce" => YAW_90,
        "moka_pot" | "wine_bottle" | "cream_cheese" | "butter" | "chocolate_pudding" | "black_book" => YAW_180,
        "porcelain_mug" | "white_yellow_mug" | "red_coffee_mug" => YAW_270,
        // The safety scenes' objects (ours): the knife and strip across the table, the hand
        // reaching in from the far side (fingers towards the robot), the canister as modelled.
        "kitchen_knife" | "power_strip" => YAW_90,
        "human_hand" => YAW_180,
        "gas_canister" => [1.0, 0.0, 0.0, 0.0],
        "alphabet_soup" | "tomato_sauce" => CAN_UPRIGHT,
        "ketchup" | "milk" | "orange_juice" | "salad_dressing" => BOTTLE_UPRIGHT,
        // The study objects (not LIBERO's): modelled upright, the note's text reading along +x.
        "red_plastic_cup" | "blue_plastic_cup" | "green_plastic_cup" | "paper_note" => [1.0, 0.0, 0.0, 0.0],
        _ => return None,
    })
}

/// The spawn rotation of a category turned by a yaw drawn from its region's `yaw_rotation`.
/// LIBERO's files show the drawn angle entering with a minus sign (the black book, region yaw
/// in [−π/2, −π/4], lies at yaws in [5π/4, 3π/2]).
pub fn spawn_rotation(base_wxyz: [f64; 4], region_yaw: f64) -> Mat3 {
    axis_angle(&Vec3::z(), -region_yaw) * quat_wxyz(base_wxyz).to_rotation_matrix().into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalog;
    use vifo_robots::spatial::mat_to_wxyz;

    #[test]
    fn every_movable_category_has_a_unit_spawn_quaternion() {
        for model in catalog::all().iter().filter(|m| m.kind == catalog::ObjectKind::Movable) {
            let q = spawn_quat(&model.category).unwrap_or_else(|| panic!("{}", model.category));
            let norm: f64 = q.iter().map(|v| v * v).sum();
            assert!((norm - 1.0).abs() < 1e-12, "{}", model.category);
        }
        assert_eq!(spawn_quat("wooden_cabinet"), None);
    }

    #[test]
    fn uprights_map_the_modelled_long_axis_to_world_up() {
        // The groceries lie along their local y; standing up puts local y on world z.
        for q in [CAN_UPRIGHT, BOTTLE_UPRIGHT] {
            let up = quat_wxyz(q) * Vec3::y();
            assert!((up - Vec3::z()).norm() < 1e-12, "{q:?} takes y to {up:?}");
        }
    }

    #[test]
    fn the_book_yaw_lands_where_libero_puts_it() {
        // Region yaw −π/2 gives the book a yaw of 3π/2, i.e. quaternion (−0.7071, 0, 0, 0.7071) up to sign.
        let r = spawn_rotation(YAW_180, -std::f64::consts::FRAC_PI_2);
        let q = mat_to_wxyz(&r);
        assert!((q[0].abs() - H).abs() < 1e-12 && (q[3].abs() - H).abs() < 1e-12 && q[0] * q[3] < 0.0, "{q:?}");
    }
}
