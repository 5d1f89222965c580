//! The Bayesian optimiser on standard test functions: accuracy within a budget, bit-for-bit
//! reproducibility, failed evaluations, and the comparison with random sampling.

use stoss::optimise::functions::{
    branin, branin_bounds, hartmann6, hartmann6_bounds, BRANIN_MIN, HARTMANN6_MIN,
};
use stoss::optimise::{
    evaluations_to_target, minimise, run, AskTell, BayesianOptimiser, Kernel, OptimiserSettings,
    RandomSearch,
};

fn branin_batch(xs: &[Vec<f64>]) -> Vec<Option<f64>> {
    xs.iter().map(|x| Some(branin(x))).collect()
}

/// Every proposal of a Branin run, in order.
fn branin_proposals(seed: u64, batch: usize, budget: usize) -> Vec<Vec<f64>> {
    let settings = OptimiserSettings::new(2, budget, seed).with_batch(batch);
    let mut bo = BayesianOptimiser::new(branin_bounds(), settings).unwrap();
    run(&mut bo, branin_batch).unwrap();
    bo.evaluations().iter().map(|e| e.x.clone()).collect()
}

#[test]
fn branin_minimum_within_forty_evaluations() {
    // GOAL: the optimiser finds a global minimum of Branin to 1e-2 within 40 evaluations.
    // SETUP: Branin on [-5, 10] x [0, 15], seed 42, design 6 (3 x dim), batches of 2, budget 40.
    // REFERENCE: global minimum 5 / (4 pi) = 0.397887 (Dixon & Szego 1978), at three points.
    let settings = OptimiserSettings::new(2, 40, 42).with_batch(2);
    let outcome = minimise(branin_batch, &branin_bounds(), &settings).unwrap();
    assert_eq!(outcome.evaluations.len(), 40);
    assert!(
        outcome.value - BRANIN_MIN < 1e-2,
        "best {} at {:?}",
        outcome.value,
        outcome.x
    );
    let hit = evaluations_to_target(&outcome.evaluations, BRANIN_MIN + 1e-2);
    println!(
        "Branin: best {} at {:?}, target hit after {hit:?} evaluations",
        outcome.value, outcome.x
    );
}

#[test]
fn matern_kernel_also_finds_the_branin_minimum() {
    // GOAL: the Matern 5/2 alternative works as well.
    // SETUP: as above with Kernel::Matern52, seed 7, batch 1.
    // REFERENCE: Branin minimum 0.397887 within 1e-2 in 40 evaluations.
    let settings = OptimiserSettings::new(2, 40, 7).with_batch(1);
    let mut bo = BayesianOptimiser::new(branin_bounds(), settings)
        .unwrap()
        .with_kernel(Kernel::Matern52);
    run(&mut bo, branin_batch).unwrap();
    let (x, value) = bo.best().unwrap();
    assert!(value - BRANIN_MIN < 1e-2, "best {value} at {x:?}");
}

#[test]
fn same_seed_gives_the_same_proposals_bit_for_bit_on_any_thread_count() {
    // GOAL: runs are reproducible from the seed, independent of the number of threads.
    // SETUP: Branin, seed 3, batch 2, budget 16, run twice on the global pool and once each in
    //        1- and 3-thread rayon pools; a run with seed 4.
    // REFERENCE: identical f64 bits for every proposal of the seed-3 runs; seed 4 differs.
    let reference = branin_proposals(3, 2, 16);
    let bits = |points: &[Vec<f64>]| -> Vec<u64> {
        points.iter().flatten().map(|v| v.to_bits()).collect()
    };
    assert_eq!(bits(&reference), bits(&branin_proposals(3, 2, 16)));
    for threads in [1, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let points = pool.install(|| branin_proposals(3, 2, 16));
        assert_eq!(bits(&reference), bits(&points), "{threads} threads");
    }
    assert_ne!(bits(&reference), bits(&branin_proposals(4, 2, 16)));
}

#[test]
fn failed_region_is_avoided_and_the_minimum_still_found() {
    // GOAL: failed simulations (None) and non-finite values neither crash the run nor stop it
    //       from finding the optimum outside the failed region.
    // SETUP: Branin where x1 in [0, 6] fails (it holds the minimum at (pi, 2.275)) - returning
    //        None below x2 = 7.5 and NaN above; seed 11, batch 2, budget 40.
    // REFERENCE: one of the two other minima, 0.397887, within 1e-2; every point in the band
    //            recorded as a failure; fewer than 40% of the proposals after the design in the
    //            band (its share of the box), i.e. the optimiser steers away from it.
    let failed = |x: &[f64]| (0.0..=6.0).contains(&x[0]);
    let objective = |xs: &[Vec<f64>]| -> Vec<Option<f64>> {
        xs.iter()
            .map(|x| match (failed(x), x[1] < 7.5) {
                (true, true) => None,
                (true, false) => Some(f64::NAN),
                (false, _) => Some(branin(x)),
            })
            .collect()
    };
    let settings = OptimiserSettings::new(2, 40, 11).with_batch(2);
    let outcome = minimise(objective, &branin_bounds(), &settings).unwrap();
    assert!(
        outcome.value - BRANIN_MIN < 1e-2,
        "best {} at {:?}",
        outcome.value,
        outcome.x
    );
    assert!(!failed(&outcome.x));
    let in_band = outcome.evaluations.iter().filter(|e| failed(&e.x)).count();
    assert_eq!(outcome.failures(), in_band);
    let proposals_in_band = outcome.evaluations[6..]
        .iter()
        .filter(|e| failed(&e.x))
        .count();
    assert!(
        proposals_in_band < 34 * 4 / 10,
        "{proposals_in_band} of 34 proposals in the failed band"
    );
}

/// Runs `optimiser` until `target` is reached (or the budget is spent): the 1-based number of
/// evaluations needed.
fn evaluations_until(
    optimiser: &mut dyn AskTell,
    f: fn(&[f64]) -> f64,
    target: f64,
) -> Option<usize> {
    loop {
        let points = optimiser.ask();
        if points.is_empty() {
            return None;
        }
        let values: Vec<Option<f64>> = points.iter().map(|x| Some(f(x))).collect();
        optimiser.tell(&points, &values).unwrap();
        if let Some(n) = evaluations_to_target(optimiser.evaluations(), target) {
            return Some(n);
        }
    }
}

#[test]
fn bayesian_optimisation_beats_random_sampling_on_branin() {
    // GOAL: the GP-BO needs fewer evaluations than random Latin hypercube sampling to reach
    //       the target (issue 6: a BO that does not beat random sampling is a defect).
    // SETUP: Branin, target 0.397887 + 1e-2, seeds 0..10, batch 2, budget 40 for BO and 200
    //        for random search (not reached counts as budget + 1). The full comparison, with
    //        CMA-ES and Hartmann-6, is `cargo bench -p stoss --bench optimise`.
    // REFERENCE: BO reaches the target in at least 9 of 10 seeds, with a median below random
    //            search's (docs/calibration.md: 22 against more than 3000).
    let target = BRANIN_MIN + 1e-2;
    let median = |mut v: Vec<usize>| {
        v.sort_unstable();
        (v[v.len() / 2 - 1] + v[v.len() / 2]) as f64 / 2.0
    };
    let (mut bo_hits, mut random_hits) = (Vec::new(), Vec::new());
    for seed in 0..10 {
        let settings = OptimiserSettings::new(2, 40, seed).with_batch(2);
        let mut bo = BayesianOptimiser::new(branin_bounds(), settings.clone()).unwrap();
        bo_hits.push(evaluations_until(&mut bo, branin, target).unwrap_or(41));
        let settings = OptimiserSettings {
            budget: 200,
            ..settings
        };
        let mut random = RandomSearch::new(branin_bounds(), &settings).unwrap();
        random_hits.push(evaluations_until(&mut random, branin, target).unwrap_or(201));
    }
    println!("BO {bo_hits:?}\nrandom {random_hits:?}");
    assert!(bo_hits.iter().filter(|&&n| n <= 40).count() >= 9);
    assert!(median(bo_hits) < median(random_hits));
}

#[test]
fn hartmann6_within_ten_percent_in_sixty_evaluations() {
    // GOAL: the optimiser also works in 6-D, where random sampling is hopeless.
    // SETUP: Hartmann-6 on [0, 1]^6, seed 1, design 18 (3 x dim), batch 2, budget 60; stop at
    //        the target.
    // REFERENCE: global minimum -3.32237 (Dixon & Szego 1978); target -3.0 (within 10%), which
    //            random LHS reached in 1 of 10 seeds within 3000 evaluations and BO in a
    //            median of 36 (docs/calibration.md).
    let settings = OptimiserSettings::new(6, 60, 1).with_batch(2);
    let mut bo = BayesianOptimiser::new(hartmann6_bounds(), settings).unwrap();
    let hit = evaluations_until(&mut bo, hartmann6, -3.0);
    println!("Hartmann-6: f <= -3 after {hit:?}, best {:?}", bo.best());
    assert!(hit.is_some_and(|n| n <= 60), "{:?}", bo.best());
    // No value below the global minimum: the function and the bookkeeping agree.
    assert!(bo.best().is_some_and(|b| b.1 >= HARTMANN6_MIN - 1e-5));
}
