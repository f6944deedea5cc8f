//! Materials for surfaces that LIBERO draws with a texture and we draw in one colour.
//!
//! MuJoCo's fixed-function lighting adds the specular term before the texture is applied
//! (`GL_MODULATE`), so a textured surface's highlight is tinted and dimmed by the texture. With
//! the texture replaced by its mean colour, scaling the specular reflectance by that colour's
//! mean keeps dark wood dark and white plates bright, as in LIBERO's images.

use vifo_render::Material;

/// A MuJoCo material with `specular` and `shininess` whose texture has the mean colour `rgba`.
pub fn textured(rgba: [f32; 4], specular: f32, shininess: f32) -> Material {
    let mean = (rgba[0] + rgba[1] + rgba[2]) / 3.0;
    Material { rgba, specular: specular * mean, shininess, ..Material::default() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn highlights_scale_with_the_texture_colour() {
        assert_eq!(textured([1.0, 1.0, 1.0, 1.0], 0.5, 0.5).specular, 0.5);
        let dark = textured([0.2, 0.1, 0.0, 1.0], 0.5, 0.3);
        assert!((dark.specular - 0.05).abs() < 1e-6 && dark.shininess == 0.3);
    }
}
