//! Reading the spec and the block file strictly: a list of coordinates has exactly the
//! values it should (serde's arrays read the first three of `[5, 5, 5, 5]` and leave the
//! rest, which the TOML reader then drops and the JSON reader reports as "trailing
//! characters"), and a table of fields is a table (serde's derived structs also take a
//! list of their fields' values in order, `options = [1e9, 0.5, "drop"]`, which bypasses
//! the check of unknown fields).
//!
//! Fields use it through `#[serde(deserialize_with = "strict::read")]` (with `default` for
//! an optional field); a whole file through [`Table`].

use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::marker::PhantomData;

/// A value read strictly (see the module's documentation).
pub(crate) trait Strict<'de>: Sized {
    /// Reads the value.
    fn strict<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error>;
}

/// `deserialize_with` for a strictly read field.
pub(crate) fn read<'de, D: Deserializer<'de>, T: Strict<'de>>(d: D) -> Result<T, D::Error> {
    T::strict(d)
}

/// A value read strictly, for a whole file (`serde_json::from_str::<Table<RawSpec>>`).
pub(crate) struct Table<T>(pub T);

impl<'de, T: Strict<'de>> Deserialize<'de> for Table<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        T::strict(d).map(Table)
    }
}

/// A list of exactly `N` numbers.
impl<'de, const N: usize> Strict<'de> for [f64; N] {
    fn strict<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Exact<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for Exact<N> {
            type Value = [f64; N];
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                // The words of serde's own arrays, which `messages::plain` rewrites.
                write!(f, "an array of length {N}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut values = [0.0; N];
                for (k, value) in values.iter_mut().enumerate() {
                    match seq.next_element::<f64>()? {
                        Some(v) => *value = v,
                        None => return Err(de::Error::invalid_length(k, &self)),
                    }
                }
                let mut count = N;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    count += 1;
                }
                if count > N {
                    return Err(de::Error::invalid_length(count, &self));
                }
                Ok(values)
            }
        }
        d.deserialize_seq(Exact::<N>)
    }
}

/// A list of values each read strictly.
impl<'de, T: Strict<'de>> Strict<'de> for Vec<T> {
    fn strict<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct List<T>(PhantomData<T>);
        impl<'de, T: Strict<'de>> Visitor<'de> for List<T> {
            type Value = Vec<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a sequence")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
                while let Some(v) = seq.next_element_seed(Seed::<T>(PhantomData))? {
                    out.push(v);
                }
                Ok(out)
            }
        }
        d.deserialize_seq(List::<T>(PhantomData))
    }
}

/// An optional value (`null` in JSON is none), read strictly when given.
impl<'de, T: Strict<'de>> Strict<'de> for Option<T> {
    fn strict<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Maybe<T>(PhantomData<T>);
        impl<'de, T: Strict<'de>> Visitor<'de> for Maybe<T> {
            type Value = Option<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("option")
            }
            fn visit_none<E: de::Error>(self) -> Result<Self::Value, E> {
                Ok(None)
            }
            fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
                Ok(None)
            }
            fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
                T::strict(d).map(Some)
            }
        }
        d.deserialize_option(Maybe::<T>(PhantomData))
    }
}

struct Seed<T>(PhantomData<T>);

impl<'de, T: Strict<'de>> DeserializeSeed<'de> for Seed<T> {
    type Value = T;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        T::strict(d)
    }
}

/// A table of fields only (not a list of the fields' values in order), read by `T`'s own
/// `Deserialize`: its messages (unknown fields, missing fields) are kept.
pub(crate) fn table<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<T, D::Error> {
    struct Fields<T>(PhantomData<T>);
    impl<'de, T: Deserialize<'de>> Visitor<'de> for Fields<T> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            // `messages::plain` makes it "a table of fields".
            f.write_str("a map")
        }
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
            T::deserialize(de::value::MapAccessDeserializer::new(map))
        }
    }
    d.deserialize_map(Fields::<T>(PhantomData))
}

/// Makes each type a table of fields when read strictly ([`table`]).
macro_rules! tables {
    ($($t:ty),* $(,)?) => {
        $(
            impl<'de> $crate::io::strict::Strict<'de> for $t {
                fn strict<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                    $crate::io::strict::table(d)
                }
            }
        )*
    };
}
pub(crate) use tables;

tables!(crate::generation::SetRecord, crate::block::FaceOrigin);
