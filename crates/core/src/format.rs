//! Numbers written for people: the lessons' captions, the inspector, the CLI's text output.
//! A coordinate of 1e300 is written `1e300`, not as 301 digits that push a panel off the
//! screen, and ±∞ and NaN are spelled out.

/// `value` with about four significant digits: fixed-point between 0.001 and a million,
/// scientific notation beyond, `+∞`, `−∞` and `NaN` spelled out.
///
/// ```
/// use accelviz_core::format::number;
/// assert_eq!(number(4.16666), "4.167");
/// assert_eq!(number(123.456), "123.5");
/// assert_eq!(number(0.5), "0.500");
/// assert_eq!(number(-2.0), "−2.000");
/// assert_eq!(number(1e300), "1e300");
/// assert_eq!(number(-1.5e-7), "−1.5e-7");
/// assert_eq!(number(f64::INFINITY), "+∞");
/// assert_eq!(number(0.0), "0");
/// ```
pub fn number(value: f64) -> String {
    if value.is_nan() {
        return "NaN".to_owned();
    }
    if value.is_infinite() {
        return if value > 0.0 { "+∞" } else { "−∞" }.to_owned();
    }
    if value == 0.0 {
        return "0".to_owned();
    }
    let magnitude = value.abs();
    let text = if !(1e-3..1e6).contains(&magnitude) {
        // Scientific: a mantissa of up to four digits, trailing zeros dropped.
        let written = format!("{magnitude:.3e}");
        let (mantissa, exponent) = written.split_once('e').unwrap_or((&written, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    } else {
        // Four significant digits above 1 (`4.167`, `123.5`), three below (`0.500`).
        let exponent = magnitude.log10().floor() as i32;
        let digits = if magnitude >= 1.0 { 3 } else { 2 };
        let decimals = (digits - exponent).clamp(0, 6) as usize;
        format!("{magnitude:.decimals$}")
    };
    // A true minus sign: it lines up with the plus of +∞ and reads better on a projector.
    if value < 0.0 {
        format!("−{text}")
    } else {
        text
    }
}

/// A point as `(x, y)` or `(x, y, z)`, each coordinate by [`number`].
pub fn point(coordinates: &[f64]) -> String {
    let parts: Vec<String> = coordinates.iter().map(|&value| number(value)).collect();
    format!("({})", parts.join(", "))
}

/// A point in a scene of size `scale` (its bounding box's diagonal, say), each coordinate to
/// four significant digits of the scene ([`number_at_scale`]): a box bound at 9.185e-18 on a
/// mesh a metre wide is 0 up to rounding, and reads as such.
///
/// ```
/// use accelviz_core::format::point_at_scale;
/// assert_eq!(point_at_scale(&[9.185e-18, 1.837, -1.141], 3.0), "(0, 1.837, −1.141)");
/// assert_eq!(point_at_scale(&[2.99e-4, 1.0], 3.0), "(0, 1.000)");
/// assert_eq!(point_at_scale(&[-0.0344, -3.56e-4, -0.0494], 0.15), "(−0.0344, −0.0004, −0.0494)");
/// ```
pub fn point_at_scale(coordinates: &[f64], scale: f64) -> String {
    let parts: Vec<String> = coordinates
        .iter()
        .map(|&value| number_at_scale(value, scale))
        .collect();
    format!("({})", parts.join(", "))
}

/// `value` to four significant digits of `scale` (a scene's size): the same decimals for
/// every coordinate of a scene, never an exponent (a bunny's box corner is `−0.0004`, not
/// `−3.56e-4` beside `−0.0344`), and a value far below the scale is `0`.
pub fn number_at_scale(value: f64, scale: f64) -> String {
    let scale = scale.abs();
    if !value.is_finite() || !scale.is_finite() || scale == 0.0 {
        return number(value);
    }
    let decimals = (3 - scale.log10().floor() as i32).clamp(0, 12) as usize;
    let text = format!("{:.decimals$}", value.abs());
    let zero = text.chars().all(|c| c == '0' || c == '.');
    if zero {
        "0".to_owned()
    } else if value < 0.0 {
        format!("\u{2212}{text}")
    } else {
        text
    }
}

/// A count with its thousands apart (`815 859`), the way SI writes them; the space is a
/// no-break space, so a number never wraps across two lines of a panel.
pub fn count(value: usize) -> String {
    let digits = value.to_string();
    let mut grouped = String::with_capacity(digits.len() + digits.len() / 3 * 3);
    for (index, digit) in digits.chars().enumerate() {
        if index > 0 && (digits.len() - index).is_multiple_of(3) {
            grouped.push(THOUSANDS);
        }
        grouped.push(digit);
    }
    grouped
}

/// The thousands separator of [`count`]: U+00A0, the no-break space (egui, like browsers,
/// breaks lines at a thin space, even U+202F).
pub const THOUSANDS: char = '\u{a0}';

/// `value` things: `1 vertex`, `3 vertices`, `1 000 shapes` ([`count`], then the noun in the
/// number it takes).
///
/// ```
/// use accelviz_core::format::counted;
/// assert_eq!(counted(1, "vertex", "vertices"), "1 vertex");
/// assert_eq!(counted(3, "vertex", "vertices"), "3 vertices");
/// assert_eq!(counted(0, "value", "values"), "0 values");
/// ```
pub fn counted(value: usize, one: &str, many: &str) -> String {
    format!("{} {}", count(value), if value == 1 { one } else { many })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_stay_short_at_every_scale() {
        for value in [
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            123_456.0,
            999_999.9,
            1e6,
            0.001,
            0.000_999,
        ] {
            let text = number(value);
            assert!(text.chars().count() <= 10, "{value}: {text}");
        }
        assert_eq!(number(999.96), "1000.0");
        assert_eq!(number(1e6), "1e6");
        assert_eq!(number(0.001), "0.00100");
        assert_eq!(number(2.5e-4), "2.5e-4");
        assert_eq!(number(f64::NEG_INFINITY), "−∞");
        assert_eq!(number(f64::NAN), "NaN");
    }

    #[test]
    fn points_and_counts() {
        assert_eq!(point(&[1.0, -2.5]), "(1.000, −2.500)");
        assert_eq!(count(815_859), "815\u{a0}859");
        assert_eq!(count(42), "42");
        assert_eq!(count(1_000_000), "1\u{a0}000\u{a0}000");
    }
}
