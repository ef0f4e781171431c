//! `all_variants!`: declares a field-less enum and its `ALL` array of every variant in
//! declaration order, so a new variant cannot be missing from the list (a device kind missing
//! from `DeviceKind::ALL` used to show as bare). Hand-written rather than strum's
//! `VariantArray` because the program iterates `ALL` by value as an array (`for q in
//! Quantity::ALL`, `ALL.len()` in consts), which a slice does not give; `HistoryColumn::ALL`
//! is generated the same way from its table.

macro_rules! all_variants {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident {
            $($(#[$variant_meta:meta])* $variant:ident,)*
        }
    ) => {
        $(#[$meta])*
        $vis enum $name {
            $($(#[$variant_meta])* $variant,)*
        }

        impl $name {
            /// Every variant, in declaration order (generated with the enum).
            pub const ALL: [$name; [$($name::$variant),*].len()] = [$($name::$variant),*];
        }
    };
}
