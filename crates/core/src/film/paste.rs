//! Assembling a film from windows of it: `lumis merge` reads each farm tile back into a film
//! of its strip and pastes it into the film of the whole image, which is then developed as a
//! single render's film is.

use super::Film;

impl Film {
    /// Copies every pixel of `part` (colour, AOVs and the ranks of each Cryptomatte layer)
    /// into this film where `part` lies in the full image. `part` must be a window of the same
    /// full image lying inside this film's window, and this film must have a layer of the same
    /// name and levels for each of `part`'s Cryptomatte layers; the manifests are this film's
    /// (the caller merges them). Nothing is copied when an error is returned.
    pub fn paste(&mut self, part: &Film) -> Result<(), String> {
        if part.full != self.full {
            return Err(format!(
                "a window of a {}x{} image cannot be pasted into a {}x{} one",
                part.full.0, part.full.1, self.full.0, self.full.1
            ));
        }
        let (dx, dy) = (
            part.origin.0.checked_sub(self.origin.0),
            part.origin.1.checked_sub(self.origin.1),
        );
        let (Some(dx), Some(dy)) = (dx, dy) else {
            return Err("the window starts outside this film".into());
        };
        if u64::from(dx) + u64::from(part.width) > u64::from(self.width)
            || u64::from(dy) + u64::from(part.height) > u64::from(self.height)
        {
            return Err("the window reaches outside this film".into());
        }
        let mut layers = Vec::with_capacity(part.crypto.len());
        for layer in &part.crypto {
            let Some(i) = self.crypto.iter().position(|l| l.name() == layer.name()) else {
                return Err(format!(
                    "this film has no Cryptomatte layer {}",
                    layer.name()
                ));
            };
            if self.crypto[i].levels() != layer.levels() {
                return Err(format!(
                    "Cryptomatte layer {}: {} ranks per pixel here, {} in the window",
                    layer.name(),
                    self.crypto[i].levels(),
                    layer.levels()
                ));
            }
            layers.push(i);
        }
        // A pass the window has and this film has not yet is added (every tile of a render
        // has the same passes; `lumis merge` checks their headers agree).
        let mut passes = Vec::with_capacity(part.passes.len());
        for pass in &part.passes {
            let i = match self.passes.iter().position(|p| p.name() == pass.name()) {
                Some(i) => i,
                None => {
                    let n = self.rgba.len();
                    self.passes
                        .push(super::PassLayer::new(pass.name(), n, pass.is_colour()));
                    self.passes.len() - 1
                }
            };
            passes.push(i);
        }
        let (w, pw) = (self.width as usize, part.width as usize);
        for row in 0..part.height as usize {
            let from = row * pw;
            let to = (dy as usize + row) * w + dx as usize;
            self.rgba[to..to + pw].copy_from_slice(&part.rgba[from..from + pw]);
            self.aov[to..to + pw].copy_from_slice(&part.aov[from..from + pw]);
            for (pass, &i) in part.passes.iter().zip(&passes) {
                self.passes[i].values_mut()[to..to + pw]
                    .copy_from_slice(&pass.values()[from..from + pw]);
            }
            for (layer, &i) in part.crypto.iter().zip(&layers) {
                for x in 0..pw {
                    self.crypto[i].set_pixel(to + x, layer.pixel(from + x));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::cryptomatte::{CryptoLayer, Rank};
    use crate::film::{Film, PixelAov, PixelWindow};
    use crate::math::Vec4;

    #[test]
    fn windows_land_where_they_lie_in_the_full_image() {
        let window = PixelWindow {
            x0: 1,
            x1: 3,
            y0: 2,
            y1: 4,
        };
        let mut part = Film::window(4, 5, window);
        let mut layer = CryptoLayer::new("CryptoObject", &["a"], 2, 4);
        let rank = Rank {
            id: layer.id_of(0),
            coverage: 1.0,
        };
        layer.set_pixel(3, &[rank, Rank::default()]);
        part.add_crypto(layer);
        let hit = PixelAov {
            prim_id: 7,
            ..PixelAov::MISS
        };
        part.set(1, 1, Vec4::ONE, hit);
        let mut full = Film::new(4, 5);
        full.add_crypto(CryptoLayer::new("CryptoObject", &["a"], 2, 20));
        full.paste(&part).unwrap();
        assert_eq!(full.pixel(2, 3), Vec4::ONE);
        assert_eq!(full.pixel_aov(2, 3), hit);
        assert_eq!(full.crypto()[0].pixel(3 * 4 + 2)[0], rank);
        assert_eq!(full.rgba().iter().filter(|&&p| p == Vec4::ONE).count(), 1);

        let mut other = Film::new(4, 6);
        assert!(other.paste(&part).is_err(), "another image");
        let mut bare = Film::new(4, 5);
        assert!(bare.paste(&part).is_err(), "no such layer");
        assert_eq!(bare, Film::new(4, 5), "nothing copied");
        let mut small = Film::window(4, 5, PixelWindow::full(2, 3));
        assert!(small.paste(&part).is_err(), "outside");
    }
}
