//! Tables that name their variant in a `kind` key (`[texture.synth]`,
//! `[rolling.tread]`, an asperity's `shape`, `[material.viscoelastic.shift]`).
//!
//! Why not `#[serde(tag = "kind")]`: an internally tagged enum buffers the
//! table before it picks the variant, so a value of the wrong type (`nx =
//! -1`) was reported as "invalid value: integer `-1`, expected usize" with
//! no key. Here the table is read, `kind` taken out, and the rest handed to
//! the enum's externally tagged derive (`#[serde(remote = "Self")]`) as
//! `{ kind = { … } }`: TOML's own reader then names the key ("in `nx`").

use serde::Deserializer;
use serde::de::{Deserialize, Error};

/// The table `d` as `{ kind = { the other keys } }`.
pub(super) fn by_kind<'de, D: Deserializer<'de>>(d: D) -> Result<toml::Value, D::Error> {
    let mut table = toml::Table::deserialize(d)?;
    let kind = match table.remove("kind") {
        Some(toml::Value::String(kind)) => kind,
        Some(other) => {
            return Err(D::Error::custom(format!(
                "`kind` must be a string, got {other}"
            )));
        }
        None => return Err(D::Error::missing_field("kind")),
    };
    let mut outer = toml::Table::new();
    outer.insert(kind, toml::Value::Table(table));
    Ok(toml::Value::Table(outer))
}

/// `impl Deserialize` for enums derived with `#[serde(remote = "Self")]`
/// (externally tagged, `rename_all = "snake_case"`), read by [`by_kind`].
macro_rules! deserialize_by_kind {
    ($($t:ty),* $(,)?) => {$(
        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let value = $crate::scenario::kind_tagged::by_kind(d)?;
                // The derived, externally tagged reader (inherent, from
                // `remote = "Self"`).
                <$t>::deserialize(value).map_err(serde::de::Error::custom)
            }
        }
    )*};
}
pub(super) use deserialize_by_kind;
