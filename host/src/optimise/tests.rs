use super::*;

fn sphere(x: &[f64]) -> f64 {
    x.iter().map(|v| (v - 0.3).powi(2)).sum()
}

fn batch_of(f: fn(&[f64]) -> f64) -> impl Fn(&[Vec<f64>]) -> Vec<Option<f64>> {
    move |xs| xs.iter().map(|x| Some(f(x))).collect()
}

#[test]
fn bounds_reject_invalid_boxes_and_scale_round_trip() {
    // GOAL: bounds are validated with typed errors and scale in and out of the unit cube.
    // SETUP: empty, ragged, inverted and infinite boxes; a valid box and a point in it.
    // REFERENCE: the matching OptimiseError variants; round trip to 1e-15 relative.
    assert_eq!(
        Bounds::new(vec![], vec![]),
        Err(OptimiseError::NoParameters)
    );
    assert!(matches!(
        Bounds::new(vec![0.0], vec![1.0, 2.0]),
        Err(OptimiseError::BoundsLength { lower: 1, upper: 2 })
    ));
    assert!(matches!(
        Bounds::new(vec![0.0, 2.0], vec![1.0, 1.0]),
        Err(OptimiseError::InvalidBound { index: 1, .. })
    ));
    assert!(matches!(
        Bounds::from_pairs(&[(0.0, f64::INFINITY)]),
        Err(OptimiseError::InvalidBound { index: 0, .. })
    ));
    let bounds = Bounds::new(vec![-5.0, 1e8], vec![10.0, 3e9]).unwrap();
    let x = vec![2.5, 7.7e8];
    let back = bounds.from_unit(&bounds.to_unit(&x));
    for (a, b) in x.iter().zip(&back) {
        assert!((a - b).abs() <= 1e-15 * a.abs(), "{a} {b}");
    }
    assert_eq!(bounds.from_unit(&[0.0, 1.0]), vec![-5.0, 3e9]);
    assert!(bounds.check(0, &[10.0, 1e8]).is_ok());
    assert!(matches!(
        bounds.check(3, &[10.5, 1e8]),
        Err(OptimiseError::PointOutOfBounds {
            point: 3,
            coordinate: 0,
            ..
        })
    ));
    assert!(matches!(
        bounds.check(0, &[f64::NAN, 1e8]),
        Err(OptimiseError::PointOutOfBounds { .. })
    ));
}

#[test]
fn settings_follow_seed_000_and_are_validated() {
    // GOAL: the default design is 3 x dimension (seed 000 sec. 4.1) within the budget, and
    //       invalid settings are errors, not panics.
    // SETUP: 6 parameters with budgets 60 and 10; zero budget, batch and design.
    // REFERENCE: initial 18, then 10; InvalidSettings for each bad value.
    let s = OptimiserSettings::new(6, 60, 1);
    assert_eq!(s.initial, 18);
    assert!(s.batch >= 1);
    assert_eq!(OptimiserSettings::new(6, 10, 1).initial, 10);
    assert!(s.validate().is_ok());
    for bad in [
        OptimiserSettings {
            budget: 0,
            ..s.clone()
        },
        OptimiserSettings {
            batch: 0,
            ..s.clone()
        },
        OptimiserSettings {
            initial: 0,
            ..s.clone()
        },
        OptimiserSettings {
            initial: 61,
            ..s.clone()
        },
    ] {
        assert!(matches!(
            bad.validate(),
            Err(OptimiseError::InvalidSettings(_))
        ));
        assert!(BayesianOptimiser::new(Bounds::unit(6).unwrap(), bad).is_err());
    }
}

#[test]
fn latin_hypercubes_have_one_point_per_stratum_and_are_reproducible() {
    // GOAL: the initial design and the random baseline are Latin hypercubes, reproducible
    //       from their seed.
    // SETUP: 12 points in 4-D, seeds 3 and 4, optimised (ESE) and plain; also 1 and 0 points.
    // REFERENCE: each coordinate has exactly one point in each of the 12 strata; the same
    //            seed gives identical bits, another seed another design.
    type Design = fn(usize, usize, u64) -> Result<Vec<Vec<f64>>, OptimiseError>;
    for lhs in [latin_hypercube as Design, random_latin_hypercube] {
        let design = lhs(12, 4, 3).unwrap();
        assert_eq!(design.len(), 12);
        for k in 0..4 {
            let mut strata: Vec<usize> = design
                .iter()
                .map(|p| ((p[k] * 12.0).floor() as usize).min(11))
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..12).collect::<Vec<_>>(), "coordinate {k}");
        }
        assert_eq!(design, lhs(12, 4, 3).unwrap());
        assert_ne!(design, lhs(12, 4, 4).unwrap());
        assert_eq!(lhs(1, 3, 0).unwrap().len(), 1);
        assert!(lhs(0, 3, 0).unwrap().is_empty());
        assert_eq!(lhs(5, 0, 0), Err(OptimiseError::NoParameters));
    }
}

#[test]
fn bayesian_optimiser_spends_exactly_its_budget_in_batches() {
    // GOAL: ask/tell bookkeeping: the first ask is the design, later asks are batches, the
    //       budget is never exceeded, and points stay in the bounds.
    // SETUP: 3-D sphere on [-1, 2]^3, budget 16, design 9, batch 4.
    // REFERENCE: batch sizes 9, 4, 3, then empty; 16 evaluations.
    let bounds = Bounds::new(vec![-1.0; 3], vec![2.0; 3]).unwrap();
    let settings = OptimiserSettings {
        budget: 16,
        initial: 9,
        batch: 4,
        seed: 5,
    };
    let mut bo = BayesianOptimiser::new(bounds.clone(), settings).unwrap();
    let mut sizes = Vec::new();
    loop {
        let points = bo.ask();
        if points.is_empty() {
            break;
        }
        sizes.push(points.len());
        for (i, x) in points.iter().enumerate() {
            assert!(bounds.check(i, x).is_ok(), "{x:?}");
        }
        let values: Vec<Option<f64>> = points.iter().map(|x| Some(sphere(x))).collect();
        bo.tell(&points, &values).unwrap();
    }
    assert_eq!(sizes, vec![9, 4, 3]);
    assert_eq!(bo.evaluations().len(), 16);
    assert_eq!(bo.pending(), 0);
}

#[test]
fn points_told_before_the_first_ask_count_towards_the_design() {
    // GOAL: a warm start (evaluations told before any ask, as a leave-one-out fold is given
    //       its model's earlier simulations) shortens the Latin hypercube by what it told,
    //       and counts towards the budget.
    // SETUP: 3-D sphere on [-1, 2]^3, design 9, batch 2; warm starts of 4 points (budget
    //        4 + 7) and of 10 points (budget 10 + 3).
    // REFERENCE: batches 5, 2 (design filled, then proposals) and 2, 1 (no design at all);
    //            the budget is spent exactly.
    let bounds = Bounds::new(vec![-1.0; 3], vec![2.0; 3]).unwrap();
    let warm = latin_hypercube(10, 3, 77).unwrap();
    for (told, fresh, expected) in [(4, 7, vec![5, 2]), (10, 3, vec![2, 1])] {
        let settings = OptimiserSettings {
            budget: told + fresh,
            initial: 9,
            batch: 2,
            seed: 5,
        };
        let mut bo = BayesianOptimiser::new(bounds.clone(), settings).unwrap();
        let points: Vec<Vec<f64>> = warm[..told].iter().map(|u| bounds.from_unit(u)).collect();
        let values: Vec<Option<f64>> = points.iter().map(|x| Some(sphere(x))).collect();
        bo.tell(&points, &values).unwrap();
        let mut sizes = Vec::new();
        loop {
            let asked = bo.ask();
            if asked.is_empty() {
                break;
            }
            sizes.push(asked.len());
            let values: Vec<Option<f64>> = asked.iter().map(|x| Some(sphere(x))).collect();
            bo.tell(&asked, &values).unwrap();
        }
        assert_eq!(sizes, expected, "warm start of {told}");
        assert_eq!(bo.evaluations().len(), told + fresh);
    }
}

#[test]
fn asking_again_before_telling_gives_new_points() {
    // GOAL: pending points enter the surrogate as constant lies, so a second ask before the
    //       tell does not repeat them.
    // SETUP: 2-D sphere, design of 6 told, then two asks of batch 2 without a tell.
    // REFERENCE: four distinct points.
    let bounds = Bounds::unit(2).unwrap();
    let settings = OptimiserSettings {
        budget: 20,
        initial: 6,
        batch: 2,
        seed: 9,
    };
    let mut bo = BayesianOptimiser::new(bounds, settings).unwrap();
    let design = bo.ask();
    let values: Vec<Option<f64>> = design.iter().map(|x| Some(sphere(x))).collect();
    bo.tell(&design, &values).unwrap();
    let mut points = bo.ask();
    points.extend(bo.ask());
    assert_eq!(points.len(), 4);
    assert_eq!(bo.pending(), 4);
    for i in 0..4 {
        for j in 0..i {
            assert_ne!(points[i], points[j]);
        }
    }
}

#[test]
fn tell_rejects_bad_input_and_records_nothing() {
    // GOAL: misuse of tell is a typed error that leaves the optimiser unchanged; non-finite
    //       values are failures, not errors.
    // SETUP: mismatched lengths, a wrong dimension, a point outside the box, then NaN and
    //        infinite values.
    // REFERENCE: LengthMismatch, DimensionMismatch, PointOutOfBounds; two failures recorded.
    let mut bo = BayesianOptimiser::new(
        Bounds::unit(2).unwrap(),
        OptimiserSettings::new(2, 10, 0).with_batch(1),
    )
    .unwrap();
    let p = vec![vec![0.5, 0.5]];
    assert!(matches!(
        bo.tell(&p, &[]),
        Err(OptimiseError::LengthMismatch { .. })
    ));
    assert!(matches!(
        bo.tell(&[vec![0.5]], &[Some(1.0)]),
        Err(OptimiseError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        bo.tell(&[vec![0.5, 0.5], vec![1.5, 0.0]], &[Some(1.0), Some(2.0)]),
        Err(OptimiseError::PointOutOfBounds { point: 1, .. })
    ));
    assert!(bo.evaluations().is_empty());
    bo.tell(
        &[vec![0.1, 0.1], vec![0.2, 0.2]],
        &[Some(f64::NAN), Some(f64::INFINITY)],
    )
    .unwrap();
    assert_eq!(bo.failures(), 2);
    assert_eq!(bo.best(), None);
}

#[test]
fn every_evaluation_failing_never_crashes() {
    // GOAL: a run where every simulation fails ends normally with a typed error.
    // SETUP: minimise an objective that always returns None, 2-D, budget 12, batch 3.
    // REFERENCE: NoSuccessfulEvaluation { evaluations: 12 }; space-filling proposals used.
    let bounds = Bounds::unit(2).unwrap();
    let settings = OptimiserSettings::new(2, 12, 1).with_batch(3);
    let result = minimise(|xs| vec![None; xs.len()], &bounds, &settings);
    assert_eq!(
        result,
        Err(OptimiseError::NoSuccessfulEvaluation { evaluations: 12 })
    );
    let mut bo = BayesianOptimiser::new(bounds, settings).unwrap();
    run(&mut bo, |xs| vec![None; xs.len()]).unwrap();
    assert_eq!(bo.fallbacks(), 6);
}

#[test]
fn an_objective_returning_the_wrong_number_of_values_is_an_error() {
    // GOAL: a broken objective is reported, not a panic.
    // SETUP: an objective that returns one value fewer than points.
    // REFERENCE: ObjectiveLength { expected: 6, found: 5 } on the initial design.
    let result = minimise(
        |xs| vec![Some(0.0); xs.len() - 1],
        &Bounds::unit(2).unwrap(),
        &OptimiserSettings::new(2, 10, 0),
    );
    assert_eq!(
        result,
        Err(OptimiseError::ObjectiveLength {
            expected: 6,
            found: 5
        })
    );
}

#[test]
fn baselines_spend_their_budget_and_improve() {
    // GOAL: the random-search and CMA-ES baselines follow the same ask/tell contract.
    // SETUP: 3-D sphere centred at 0.3 on [0, 1]^3, budget 150, batch 2, seed 11.
    // REFERENCE: 150 evaluations each; random search below 0.05 (the nearest of 150 uniform
    //            points lies within 0.22 of the centre with probability 0.999); CMA-ES below
    //            1e-3 (linear convergence from 0.1, about a decade per 40 evaluations here).
    let bounds = Bounds::unit(3).unwrap();
    let settings = OptimiserSettings::new(3, 150, 11).with_batch(2);
    let mut random = RandomSearch::new(bounds.clone(), &settings).unwrap();
    run(&mut random, batch_of(sphere)).unwrap();
    assert_eq!(random.evaluations().len(), 150);
    let best_random = random.best().unwrap().1;
    assert!(best_random < 0.05, "{best_random}");
    let mut cma = CmaEs::new(bounds, &settings).unwrap();
    run(&mut cma, batch_of(sphere)).unwrap();
    assert_eq!(cma.evaluations().len(), 150);
    let best_cma = cma.best().unwrap().1;
    assert!(best_cma < 1e-3, "{best_cma}");
}

#[test]
fn evaluations_to_target_counts_the_first_hit() {
    // GOAL: the benchmark metric is the 1-based index of the first value at or below target.
    // SETUP: values [3, None, 1, 0.5].
    // REFERENCE: target 1 -> 3; target 0.1 -> None.
    let evaluations: Vec<Evaluation> = [Some(3.0), None, Some(1.0), Some(0.5)]
        .iter()
        .map(|&value| Evaluation {
            x: vec![0.0],
            value,
        })
        .collect();
    assert_eq!(evaluations_to_target(&evaluations, 1.0), Some(3));
    assert_eq!(evaluations_to_target(&evaluations, 0.1), None);
}

#[test]
fn optimisers_can_move_between_threads() {
    // GOAL: the optimisers can live in a calibration driver that runs instances on a thread
    //       pool (the driver's proposer trait requires Send).
    // SETUP: compile-time check.
    // REFERENCE: BayesianOptimiser, RandomSearch and CmaEs are Send + Sync.
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<BayesianOptimiser>();
    assert_send_sync::<RandomSearch>();
    assert_send_sync::<CmaEs>();
}
