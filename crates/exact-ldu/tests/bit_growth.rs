//! Bit growth of the factors (thesis figures 7.1–7.4): linear in the rank with GCD or Turner
//! simplification, exponential without.

use exact_ldu::{Int, Ldu, Ring, Simplification};

/// A small deterministic generator (xorshift64*), so the test sees the same matrices every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `-bound..=bound`.
    fn symmetric(&mut self, bound: i64) -> i64 {
        (self.next() % (2 * bound as u64 + 1)) as i64 - bound
    }
}

/// A 20 × 20 matrix of rank `rank` with entries of about `bits` bits: the product of random
/// `20 × rank` and `rank × 20` factors with entries in `±⌈√(2^(bits−1)/rank)⌉` (thesis 7.3.1).
fn rank_deficient(rng: &mut Rng, size: usize, rank: usize, bits: u32) -> Vec<Vec<Int>> {
    let bound = ((2f64.powi(bits as i32 - 1) / rank as f64).sqrt().ceil()) as i64;
    let p: Vec<Vec<i64>> = (0..size)
        .map(|_| (0..rank).map(|_| rng.symmetric(bound)).collect())
        .collect();
    let q: Vec<Vec<i64>> = (0..rank)
        .map(|_| (0..size).map(|_| rng.symmetric(bound)).collect())
        .collect();
    p.iter()
        .map(|prow| {
            (0..size)
                .map(|j| Int::from_i64(prow.iter().zip(&q).map(|(a, qr)| a * qr[j]).sum()))
                .collect()
        })
        .collect()
}

/// Largest factor entry, in bits, over `samples` random matrices of the given rank.
fn max_bits(method: Simplification, rank: usize, samples: usize, seed: u64) -> u64 {
    let mut rng = Rng(seed);
    (0..samples)
        .map(|_| {
            let a = rank_deficient(&mut rng, 20, rank, 10);
            let ldu = Ldu::factor(a, 20, method).expect("square");
            assert_eq!(ldu.rank(), rank, "random factors of rank {rank}");
            ldu.max_entry_bits()
        })
        .max()
        .unwrap_or(0)
}

/// GCD and Turner keep the largest entry within a linear bound in the rank (about 10 bits of
/// input per rank step, as in figure 7.4), while no simplification doubles the size per step.
#[test]
fn simplified_factors_grow_linearly_in_the_rank() {
    for method in [Simplification::Gcd, Simplification::Turner] {
        let sizes: Vec<(usize, u64)> = [2, 5, 10, 15, 20]
            .iter()
            .map(|&r| (r, max_bits(method, r, 3, 0x9e37_79b9 + r as u64)))
            .collect();
        for &(r, bits) in &sizes {
            assert!(
                bits <= 14 * r as u64 + 24,
                "{method:?}: rank {r} reached {bits} bits"
            );
        }
        let b10 = sizes[2].1 as f64;
        let b20 = sizes[4].1 as f64;
        assert!(
            (1.4..=2.6).contains(&(b20 / b10)),
            "{method:?}: doubling the rank should about double the bits: {sizes:?}"
        );
    }
    let none6 = max_bits(Simplification::None, 6, 2, 7);
    let gcd6 = max_bits(Simplification::Gcd, 6, 2, 7);
    assert!(
        none6 > 4 * gcd6,
        "no simplification should blow up: {none6} vs {gcd6} bits"
    );
}

/// Prints the table of max bit size against rank for None / GCD / Turner (figure 7.4).
/// `cargo test -p exact-ldu --release --test bit_growth -- --ignored --nocapture`
#[test]
#[ignore = "sweep that prints a table; takes a while"]
fn bit_growth_table() {
    println!("rank  none  gcd  turner   (20 x 20, 10-bit entries, max over 20 matrices)");
    for rank in [1, 2, 3, 4, 5, 6, 8, 10, 12, 14, 16, 18, 20] {
        let none = if rank <= 12 {
            max_bits(Simplification::None, rank, 20, 11 + rank as u64).to_string()
        } else {
            "-".to_string()
        };
        let gcd = max_bits(Simplification::Gcd, rank, 20, 11 + rank as u64);
        let turner = max_bits(Simplification::Turner, rank, 20, 11 + rank as u64);
        println!("{rank:>4}  {none:>6}  {gcd:>4}  {turner:>6}");
    }
}
