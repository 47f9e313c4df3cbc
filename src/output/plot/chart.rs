//! What the plots share: the embedded font (DejaVu Sans from the `dejavu` crate, registered
//! once with plotters' ab_glyph text), text sizes that follow the picture, the tolerance
//! bands of the colour map, and a legend of swatches drawn with plotters into an RGB buffer.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// The drawing area every plot draws on: an RGB buffer.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// What drawing returns: plotters' errors (there are none drawing into a buffer of the
/// right size) boxed.
pub(crate) type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// Register the embedded font as plotters' `sans-serif` (once per process).
pub(crate) fn font_once() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TTF shipped by the crate; a failure leaves text undrawn.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
        let _ = plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

/// The body text size (pixels) of a `w` x `h` picture: 1/60 of the geometric mean of its
/// sides (20 px at 1600 x 900), 11 px at least.
pub(crate) fn text_px(w: u32, h: u32) -> f64 {
    ((w as f64 * h as f64).sqrt() / 60.0).max(11.0)
}

/// An sRGB triple as a plotters colour.
pub(crate) fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// Within the tolerance (neutral).
pub(crate) const WITHIN: [u8; 3] = [222, 222, 216];
/// Not compared (outside the drawing's span on that generator).
pub(crate) const NOT_COMPARED: [u8; 3] = [250, 250, 250];
/// Gouge 1-2x, 2-5x, over 5x the tolerance (blues, light to dark).
pub(crate) const GOUGE_BANDS: [[u8; 3]; 3] = [[165, 200, 245], [70, 130, 225], [20, 40, 150]];
/// Leftover 1-2x, 2-5x, over 5x the tolerance (oranges to dark red).
pub(crate) const LEFTOVER_BANDS: [[u8; 3]; 3] = [[250, 200, 140], [235, 120, 45], [160, 20, 20]];
/// The band edges in multiples of the tolerance.
pub(crate) const BAND_EDGES: [f64; 3] = [1.0, 2.0, 5.0];

/// The colour of a signed deviation `d` (mm, negative gouge) in the plots' tolerance
/// bands: within, 1-2x, 2-5x, over 5x the tolerance `tol`; `None` is "not compared".
pub fn band_colour(d: Option<f64>, tol: f64) -> [u8; 3] {
    let Some(d) = d else { return NOT_COMPARED };
    let k = d.abs() / tol.max(1e-12);
    if k <= BAND_EDGES[0] {
        return WITHIN;
    }
    let band = if k <= BAND_EDGES[1] {
        0
    } else if k <= BAND_EDGES[2] {
        1
    } else {
        2
    };
    if d < 0.0 {
        GOUGE_BANDS[band]
    } else {
        LEFTOVER_BANDS[band]
    }
}

/// One legend entry: a filled box, a line, or a ring, in a colour, with its text.
pub(crate) enum Swatch {
    /// A filled box.
    Fill([u8; 3]),
    /// A thick line.
    Line([u8; 3]),
    /// A ring (a marked place).
    Ring([u8; 3]),
}

/// Draw `items` as rows from `(x, y)` downwards (a column), `px` the text size; returns the
/// y below the last row.
pub(crate) fn legend_column(
    area: &Area,
    x: i32,
    y: i32,
    px: f64,
    items: &[(Swatch, String)],
) -> Res<i32> {
    let row = (px * 1.5).round() as i32;
    let sw = (px * 1.6).round() as i32;
    let style = ("sans-serif", px).into_font().color(&BLACK);
    let mut y = y;
    for (swatch, label) in items {
        swatch_at(area, x, y, sw, (px * 0.9) as i32, swatch)?;
        area.draw(&Text::new(
            label.clone(),
            (x + sw + (px * 0.5) as i32, y - (px * 0.1) as i32),
            style.clone(),
        ))?;
        y += row;
    }
    Ok(y)
}

/// Draw `items` in a row from `(x, y)` rightwards; returns the x after the last entry.
pub(crate) fn legend_row(
    area: &Area,
    x: i32,
    y: i32,
    px: f64,
    items: &[(Swatch, String)],
) -> Res<i32> {
    let sw = (px * 1.6).round() as i32;
    let style = ("sans-serif", px).into_font().color(&BLACK);
    let mut x = x;
    for (swatch, label) in items {
        swatch_at(area, x, y, sw, (px * 0.9) as i32, swatch)?;
        x += sw + (px * 0.4) as i32;
        area.draw(&Text::new(
            label.clone(),
            (x, y - (px * 0.1) as i32),
            style.clone(),
        ))?;
        let w = area
            .estimate_text_size(label, &style)
            .map_or(label.len() as i32 * px as i32 / 2, |s| s.0 as i32);
        x += w + (px * 1.2) as i32;
    }
    Ok(x)
}

fn swatch_at(area: &Area, x: i32, y: i32, w: i32, h: i32, swatch: &Swatch) -> Res<()> {
    match swatch {
        Swatch::Fill(c) => {
            area.draw(&Rectangle::new([(x, y), (x + w, y + h)], rgb(*c).filled()))?;
            area.draw(&Rectangle::new(
                [(x, y), (x + w, y + h)],
                RGBColor(120, 120, 120).stroke_width(1),
            ))?;
        }
        Swatch::Line(c) => {
            area.draw(&PathElement::new(
                vec![(x, y + h / 2), (x + w, y + h / 2)],
                rgb(*c).stroke_width(((h as f64) / 5.0).max(2.0) as u32),
            ))?;
        }
        Swatch::Ring(c) => {
            area.draw(&Circle::new(
                (x + w / 2, y + h / 2),
                h / 2,
                rgb(*c).stroke_width(2),
            ))?;
        }
    }
    Ok(())
}

/// A picture of `w` x `h` white pixels drawn by `draw` (an error leaves what was drawn).
pub(crate) fn picture<F>(w: u32, h: u32, draw: F) -> image::RgbImage
where
    F: FnOnce(&Area) -> Res<()>,
{
    picture_on(vec![255u8; w as usize * h as usize * 3], w, h, draw)
}

/// `draw` over the `w` x `h` RGB pixels `buf` (an error leaves what was drawn).
pub(crate) fn picture_on<F>(mut buf: Vec<u8>, w: u32, h: u32, draw: F) -> image::RgbImage
where
    F: FnOnce(&Area) -> Res<()>,
{
    font_once();
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let _ = draw(&root);
        let _ = root.present();
    }
    image::RgbImage::from_raw(w, h, buf).expect("the buffer has w x h x 3 bytes")
}

/// A number of millimetres with as many decimals as `step` needs.
pub(crate) fn mm(v: f64, step: f64) -> String {
    let dec = (-(step.abs().max(1e-9)).log10().floor()).clamp(0.0, 6.0) as usize;
    // No "-0.00": what rounds to zero is zero.
    let v = if v.abs() < 0.5 * 10f64.powi(-(dec as i32)) {
        0.0
    } else {
        v
    };
    format!("{v:.dec$}")
}
