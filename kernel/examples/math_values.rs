//! Evaluates stoss's `exp`, `ln` and `pow` on arguments read from standard input, for
//! `kernel/tools/math_oracle.py`, which compares them with a 50-digit oracle.
//!
//! Input: one call per line, `exp <x bits>`, `ln <x bits>` or `pow <x bits> <y bits>`, bits
//! as 16 hexadecimal digits. Output: the result's bits, one line per call.

use std::io::{BufRead, BufWriter, Write};

use stoss_kernel::math::{exp, ln, pow};

fn bits(word: Option<&str>, line: usize) -> f64 {
    let word = word.unwrap_or_else(|| panic!("line {line}: missing argument"));
    let value = u64::from_str_radix(word, 16)
        .unwrap_or_else(|_| panic!("line {line}: '{word}' is not 16 hex digits"));
    f64::from_bits(value)
}

fn main() {
    let stdin = std::io::stdin();
    let mut out = BufWriter::new(std::io::stdout().lock());
    for (index, line) in stdin.lock().lines().enumerate() {
        let line = line.expect("read standard input");
        let mut words = line.split_whitespace();
        let function = words.next().unwrap_or("");
        let x = bits(words.next(), index + 1);
        let value = match function {
            "exp" => exp(x),
            "ln" => ln(x),
            "pow" => pow(x, bits(words.next(), index + 1)),
            other => panic!("line {}: unknown function '{other}'", index + 1),
        };
        writeln!(out, "{:016x}", value.to_bits()).expect("write standard output");
    }
}
