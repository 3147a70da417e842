//! Quantities written with their unit in scenario files ("5 mm", "6.54 MPa"),
//! converted to SI on reading. A bare number is taken as SI already.

use std::fmt;
use std::marker::PhantomData;

/// A physical dimension: its name and the units it accepts (factor to SI).
pub trait Dimension {
    /// Name used in error messages.
    const NAME: &'static str;
    /// Accepted units and their factors to the SI unit.
    const UNITS: &'static [(&'static str, f64)];
}

macro_rules! dimension {
    ($ty:ident, $name:literal, [$(($unit:literal, $factor:expr)),* $(,)?]) => {
        #[doc = concat!("The ", $name, " dimension.")]
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $ty;
        impl Dimension for $ty {
            const NAME: &'static str = $name;
            const UNITS: &'static [(&'static str, f64)] = &[$(($unit, $factor)),*];
        }
    };
}

dimension!(
    LengthDim,
    "length",
    [
        ("m", 1.0),
        ("cm", 1e-2),
        ("mm", 1e-3),
        ("um", 1e-6),
        ("µm", 1e-6),
        ("μm", 1e-6),
        ("km", 1e3),
    ]
);
dimension!(
    PressureDim,
    "pressure",
    [
        ("Pa", 1.0),
        ("kPa", 1e3),
        ("MPa", 1e6),
        ("GPa", 1e9),
        ("N/m2", 1.0),
        ("N/mm2", 1e6),
    ]
);
dimension!(ForceDim, "force", [("N", 1.0), ("kN", 1e3), ("mN", 1e-3)]);
dimension!(
    AngleDim,
    "angle",
    [
        ("rad", 1.0),
        ("deg", std::f64::consts::PI / 180.0),
        ("°", std::f64::consts::PI / 180.0)
    ]
);

dimension!(
    AreaDim,
    "area",
    [
        ("m2", 1.0),
        ("m²", 1.0),
        ("cm2", 1e-4),
        ("cm²", 1e-4),
        ("mm2", 1e-6),
        ("mm²", 1e-6),
    ]
);

dimension!(
    SpeedDim,
    "speed",
    [
        ("m/s", 1.0),
        ("km/h", 1.0 / 3.6),
        ("kmh", 1.0 / 3.6),
        ("mph", 0.44704)
    ]
);

dimension!(
    TimeDim,
    "time",
    [
        ("s", 1.0),
        ("ms", 1e-3),
        ("us", 1e-6),
        ("µs", 1e-6),
        ("μs", 1e-6),
        ("min", 60.0),
    ]
);

/// A value of dimension `D`, held in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantity<D> {
    si: f64,
    dim: PhantomData<D>,
}

impl<D: Dimension> Quantity<D> {
    /// From an SI value.
    pub fn si(value: f64) -> Self {
        Self {
            si: value,
            dim: PhantomData,
        }
    }

    /// The SI value.
    pub fn value(self) -> f64 {
        self.si
    }

    /// Parses "5 mm", "5mm", "6.54 MPa", "0.5" (SI) or "1e-3 m".
    pub fn parse(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let split = text
            .char_indices()
            .find(|&(i, c)| {
                !(c.is_ascii_digit()
                    || c == '.'
                    || c == '+'
                    || c == '-'
                    || ((c == 'e' || c == 'E')
                        && i > 0
                        && text[i + 1..]
                            .starts_with(|d: char| d.is_ascii_digit() || d == '-' || d == '+')))
            })
            .map_or(text.len(), |(i, _)| i);
        let (number, unit) = (text[..split].trim(), text[split..].trim());
        let value: f64 = number.parse().map_err(|_| {
            format!(
                "`{text}` is not a {} (expected a number and a unit, like {})",
                D::NAME,
                example::<D>()
            )
        })?;
        if !value.is_finite() {
            return Err(format!("`{text}` is not a finite {}", D::NAME));
        }
        let factor = D::UNITS
            .iter()
            .find(|(u, _)| *u == unit)
            .map(|&(_, f)| f)
            .or(if unit.is_empty() { Some(1.0) } else { None })
            .ok_or_else(|| {
                let known: Vec<&str> = D::UNITS
                    .iter()
                    .map(|(u, _)| *u)
                    .filter(|u| !u.is_empty())
                    .collect();
                format!(
                    "unknown {} unit `{unit}` in `{text}` (known: {})",
                    D::NAME,
                    known.join(", ")
                )
            })?;
        Ok(Self::si(value * factor))
    }
}

fn example<D: Dimension>() -> String {
    match D::UNITS.first() {
        Some((u, _)) if !u.is_empty() => format!("\"1 {u}\""),
        _ => "0.5".into(),
    }
}

impl<'de, D: Dimension> serde::Deserialize<'de> for Quantity<D> {
    fn deserialize<De: serde::Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct Visitor<D>(PhantomData<D>);
        impl<D: Dimension> serde::de::Visitor<'_> for Visitor<D> {
            type Value = Quantity<D>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(
                    f,
                    "a {} as a number (SI) or a string with its unit",
                    D::NAME
                )
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
                if v.is_finite() {
                    Ok(Quantity::si(v))
                } else {
                    Err(E::custom(format!("{} must be finite", D::NAME)))
                }
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
                Ok(Quantity::si(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(Quantity::si(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Quantity::parse(v).map_err(E::custom)
            }
        }
        deserializer.deserialize_any(Visitor(PhantomData))
    }
}

/// A length (m).
pub type Length = Quantity<LengthDim>;
/// A pressure or modulus (Pa).
pub type Pressure = Quantity<PressureDim>;
/// A force (N).
pub type Force = Quantity<ForceDim>;
/// An angle (rad).
pub type Angle = Quantity<AngleDim>;
/// A speed (m/s).
pub type Speed = Quantity<SpeedDim>;
/// An area (m²).
pub type Area = Quantity<AreaDim>;
/// A duration (s).
pub type Time = Quantity<TimeDim>;

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_to_si() {
        assert_eq!(Length::parse("5 mm").map(Quantity::value), Ok(5e-3));
        assert_eq!(Length::parse("5mm").map(Quantity::value), Ok(5e-3));
        assert_eq!(Length::parse("-20 mm").map(Quantity::value), Ok(-20e-3));
        assert_eq!(Length::parse("1e-3 m").map(Quantity::value), Ok(1e-3));
        assert_eq!(Length::parse("2.5e-1").map(Quantity::value), Ok(0.25));
        assert!(
            (Pressure::parse("6.54 MPa")
                .map(Quantity::value)
                .unwrap_or(0.0)
                - 6.54e6)
                .abs()
                < 1e-6
        );
        assert_eq!(Force::parse("0.5 kN").map(Quantity::value), Ok(500.0));
        assert!((Area::parse("2 mm2").map(Quantity::value).unwrap_or(0.0) - 2e-6).abs() < 1e-18);
        assert!(
            (Area::parse("1.5e-6 m2").map(Quantity::value).unwrap_or(0.0) - 1.5e-6).abs() < 1e-20
        );
        assert!(
            (Angle::parse("90 deg").map(Quantity::value).unwrap_or(0.0)
                - std::f64::consts::FRAC_PI_2)
                .abs()
                < 1e-15
        );
    }

    #[test]
    fn bad_units_are_named() {
        let e = Length::parse("5 furlongs").unwrap_err();
        assert!(e.contains("unknown length unit `furlongs`"), "{e}");
        assert!(
            Length::parse("5 MPa")
                .unwrap_err()
                .contains("unknown length unit")
        );
        assert!(
            Pressure::parse("abc")
                .unwrap_err()
                .contains("not a pressure")
        );
        assert!(Length::parse("").is_err());
        assert!(Length::parse("inf mm").is_err());
    }
}
