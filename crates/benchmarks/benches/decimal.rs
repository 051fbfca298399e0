//! The decimal text of long integers: `num-bigint`'s conversion one integer at a time
//! against [`exact_ldu::decimal_texts`] (one table of powers for the batch; eight integers at a
//! time in IFMA lanes where the processor has them, else by word products), for batches shaped
//! like the exact optimum's values: 256 integers of 700 limbs (~13 500 digits, as at δ_max = 40
//! on the figure mesh), of 110 limbs (~2 100 digits, as at δ_max = 16) and of 11 limbs (~210
//! digits, as on the δ_max = 8 grid). Both on all cores, as the report converts them.
//!
//! `cargo bench -p benchmarks --bench decimal`

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

/// The `benchmarks` library declares the `ecles` binary's allocator (mimalloc); a bench links
/// it only when it uses the library, and would otherwise measure with the system's allocator.
use benchmarks as _;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use num_bigint::{BigInt, BigUint, Sign};
use std::hint::black_box;

/// `count` integers of `limbs` 64-bit limbs with pseudo-random limbs, every third negative.
fn batch(count: usize, limbs: usize) -> Vec<BigInt> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    (0..count)
        .map(|i| {
            let words: Vec<u32> = (0..2 * limbs)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    state as u32
                })
                .collect();
            let sign = if i % 3 == 0 { Sign::Minus } else { Sign::Plus };
            BigInt::from_biguint(
                sign,
                BigUint::from_slice(&words) | BigUint::from(1u8) << (64 * limbs - 1),
            )
        })
        .collect()
}

fn decimal(c: &mut Criterion) {
    use rayon::prelude::*;
    let mut group = c.benchmark_group("decimal-text");
    group.sample_size(10);
    for limbs in [11usize, 110, 700] {
        let values = batch(256, limbs);
        let refs: Vec<&BigInt> = values.iter().collect();
        let expected: Vec<String> = values.iter().map(BigInt::to_string).collect();
        assert_eq!(exact_ldu::decimal_texts(&refs), expected);
        group.bench_function(BenchmarkId::new("num-bigint", limbs), |b| {
            b.iter(|| black_box(refs.par_iter().map(|v| v.to_string()).collect::<Vec<_>>()))
        });
        group.bench_function(BenchmarkId::new("batch", limbs), |b| {
            b.iter(|| black_box(exact_ldu::decimal_texts(&refs)))
        });
    }
    group.finish();
}

criterion_group!(benches, decimal);
criterion_main!(benches);
