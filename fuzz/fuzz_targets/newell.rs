//! The Newell patch parser and tessellator on arbitrary text; the first byte picks the
//! tessellation (1..=8).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else { return };
    let text = String::from_utf8_lossy(rest);
    let tessellation = u32::from(first % 8) + 1;
    let _ = seamlit_io::newell::parse(&text, "fuzz", tessellation);
});
