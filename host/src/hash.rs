//! FNV-1a (64 bit, Fowler–Noll–Vo): the stable, platform-independent key of cached and logged
//! results (the blast-load cache, the diagnosis journal, the names of Slurm task files).

/// FNV-1a of `text`: offset basis 0xcbf29ce484222325, prime 0x100000001b3.
pub fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn fnv1a_matches_the_published_vectors() {
        // GOAL: the keys of cached results never change. SETUP: "" and "a".
        // REFERENCE: the FNV test vectors (Noll, isthe.com/chongo/tech/comp/fnv).
        assert_eq!(super::fnv1a(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(super::fnv1a("a"), 0xaf63_dc4c_8601_ec8c);
    }
}
