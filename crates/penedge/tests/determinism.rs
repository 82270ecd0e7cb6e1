//! Determinism: the system detector gives identical output (contacts, features, penetrating
//! pairs, and the contact geometry bit for bit) for any number of threads, and the same
//! contacts up to renumbering for any order of the blocks in the input.

mod support;

use penedge::generation::rng::SplitMix64;
use penedge::system::{paper_example, PairContact, PaperExample, SystemContacts};
use penedge::{BlockSystem, Tolerance};
use support::{answer, differences, jointed, pairs_of_every_type, sheared};

fn systems() -> Vec<(String, BlockSystem)> {
    vec![
        (
            "example 3".into(),
            paper_example(PaperExample::Three).unwrap(),
        ),
        ("jointed 0".into(), jointed(0)),
        ("jointed 1".into(), jointed(1)),
        ("sheared 0".into(), sheared(0)),
        ("pairs of every type".into(), pairs_of_every_type()),
    ]
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

#[test]
fn any_number_of_threads_gives_the_same_output() {
    let tol = Tolerance::default();
    for (label, sys) in systems() {
        let one = pool(1).install(|| sys.detect(&tol));
        let one_geometry = pool(1).install(|| sys.detect_with_geometry(&tol));
        assert!(!one.contacts.is_empty());
        for threads in [2, 4] {
            let p = pool(threads);
            assert_eq!(
                p.install(|| sys.detect(&tol)),
                one,
                "{label}, {threads} threads"
            );
            // Twice, to catch an order that depends on scheduling.
            assert_eq!(
                p.install(|| sys.detect(&tol)),
                one,
                "{label}, {threads} threads"
            );
            let (found, geometry) = p.install(|| sys.detect_with_geometry(&tol));
            assert_eq!(found, one_geometry.0, "{label}, {threads} threads");
            // Bit for bit: compare the bit patterns (PartialEq of f64 would accept -0 = 0).
            let bits = |g: &penedge::system::ContactGeometries| {
                let mut v: Vec<u64> = Vec::new();
                v.extend(g.normals.iter().flatten().map(|x| x.to_bits()));
                v.extend(g.distances.iter().map(|x| x.to_bits()));
                v.extend(g.areas.iter().map(|x| x.to_bits()));
                v.extend(g.points.iter().flatten().map(|x| x.to_bits()));
                v.extend(g.point_offsets.iter().copied());
                v
            };
            assert!(
                bits(&geometry) == bits(&one_geometry.1),
                "{label}, {threads} threads"
            );
        }
    }
}

/// A random permutation of `0..n` (Fisher-Yates).
fn permutation(n: usize, r: &mut SplitMix64) -> Vec<usize> {
    let mut p: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (r.next_u64() % (i as u64 + 1)) as usize;
        p.swap(i, j);
    }
    p
}

/// The contacts of the permuted system (block `k` is block `order[k]` of the original),
/// renumbered back to the original ids and sorted.
fn renumbered(found: &SystemContacts, order: &[usize]) -> SystemContacts {
    let mut contacts: Vec<PairContact> = found
        .contacts
        .iter()
        .map(|c| {
            let [i, j] = c.pair.map(|k| order[k as usize] as u32);
            let mut contact = c.contact;
            if i > j {
                std::mem::swap(&mut contact.feature_a, &mut contact.feature_b);
            }
            PairContact {
                pair: [i.min(j), i.max(j)],
                contact,
            }
        })
        .collect();
    contacts.sort_by_key(|c| c.pair);
    let mut penetrating: Vec<[u32; 2]> = found
        .penetrating
        .iter()
        .map(|p| {
            let [i, j] = p.map(|k| order[k as usize] as u32);
            [i.min(j), i.max(j)]
        })
        .collect();
    penetrating.sort();
    SystemContacts {
        contacts,
        penetrating,
    }
}

#[test]
fn any_order_of_the_blocks_gives_the_same_contacts() {
    let tol = Tolerance::default();
    let mut r = SplitMix64::new(5);
    for (label, sys) in systems() {
        let expected = sys.detect(&tol);
        let mut orders = vec![(0..sys.len()).rev().collect::<Vec<_>>()];
        orders.extend((0..3).map(|_| permutation(sys.len(), &mut r)));
        for (k, order) in orders.iter().enumerate() {
            let permuted =
                BlockSystem::new(order.iter().map(|&i| sys.blocks()[i].clone()).collect());
            let got = renumbered(&permuted.detect(&tol), order);
            assert!(
                got == expected,
                "{label}, order {k}: {}",
                differences(&answer(&expected), &answer(&got))
            );
        }
    }
}

/// A system that penetrates somewhere keeps its penetrating pairs under renumbering and
/// threads too.
#[test]
fn penetrating_pairs_are_deterministic_too() {
    let tol = Tolerance::default();
    let sys = jointed(2);
    // Every third block pushed 1 cm down: it penetrates its neighbours below.
    let blocks: Vec<_> = sys
        .blocks()
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let t = if i % 3 == 0 { -0.01 } else { 0.0 };
            b.transformed(glam::DQuat::IDENTITY, glam::DVec3::new(0.0, 0.0, t), 1.0)
        })
        .collect();
    let sys = BlockSystem::new(blocks);
    let expected = pool(1).install(|| sys.detect(&tol));
    assert!(!expected.penetrating.is_empty() && !expected.contacts.is_empty());
    assert_eq!(pool(4).install(|| sys.detect(&tol)), expected);
    let order = permutation(sys.len(), &mut SplitMix64::new(9));
    let permuted = BlockSystem::new(order.iter().map(|&i| sys.blocks()[i].clone()).collect());
    let got = renumbered(&pool(3).install(|| permuted.detect(&tol)), &order);
    assert_eq!(got, expected);
}
