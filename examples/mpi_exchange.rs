//! The MPI transport's check, run by `.ci/run` under `mpirun -np 2` and `-np 4`:
//!
//! ```sh
//! cargo build --release --features mpi --example mpi_exchange
//! mpirun -np 4 target/release/examples/mpi_exchange
//! ```
//!
//! Each rank starts with a block of a shared random particle set, migrates them to their owners
//! (bisection), sloshes them back and forth for 40 rounds migrating after each, then gathers the
//! halo. Rank 0 checks that every id is present once with its fields' bits, that each rank's
//! ghosts hold every neighbour within the halo width, and that the sums agree on every rank; a
//! failure exits non-zero. With `--lose-rank R`, rank R exits before the first exchange: the
//! whole job must stop with an error (mpirun's exit status), not hang.

use sph::distributed::mpi_world::MpiWorld;
use sph::distributed::{Communicator, Decomposition, Method, Region, gather_ghosts, migrate};
use sph::fields::Fields;
use sph::math::Vector;
use sph::physics::pcg::Pcg32;

/// Uniform draws in [0, 1) from the library's PCG32: every rank draws the same particle set.
struct Rng(Pcg32);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(Pcg32::new(seed, 0))
    }

    fn next(&mut self) -> f32 {
        self.0.next_f64() as f32
    }
}

const N: usize = 4000;
const WIDTH: f32 = 0.06;

fn particles() -> Fields<2> {
    let mut rng = Rng::new(29);
    let mut fields = Fields::with_capacity(N);
    for k in 0..N {
        let x = Vector::<2>::new(2.0 * rng.next(), rng.next());
        let u = Vector::<2>::new(rng.next(), rng.next());
        fields.push(x, u, 1.0 + rng.next(), 1000.0 + rng.next(), (k % 3) as u32);
        fields.pressure[k] = 100.0 * rng.next();
    }
    fields
}

/// Position and velocity bits, density, pressure and mass bits, by id.
fn signature(f: &Fields<2>, k: usize) -> [u32; 8] {
    [
        f.position[k][0].to_bits(),
        f.position[k][1].to_bits(),
        f.velocity[k][0].to_bits(),
        f.velocity[k][1].to_bits(),
        f.density[k].to_bits(),
        f.pressure[k].to_bits(),
        f.mass[k].to_bits(),
        f.kind[k],
    ]
}

fn fail(rank: usize, what: String) -> ! {
    eprintln!("mpi_exchange: rank {rank}: {what}");
    std::process::exit(1);
}

fn main() {
    let world = MpiWorld::initialize().unwrap_or_else(|e| fail(0, e.to_string()));
    let (rank, size) = (world.rank(), world.size());
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--lose-rank") {
        let lost: usize = args.get(k + 1).and_then(|s| s.parse().ok()).unwrap_or(1);
        if rank == lost {
            eprintln!("mpi_exchange: rank {rank} leaves before the first exchange");
            std::process::exit(3);
        }
    }
    let all = particles();
    let domain = Region::<2> {
        lo: Vector::zeros(),
        hi: Vector::<2>::new(2.0, 1.0),
    };
    let d = Decomposition::build(domain, &all.position, size, Method::Bisection);
    let mut mine = all.clone();
    mine.keep(
        &(rank * N / size..(rank + 1) * N / size)
            .map(|k| k as u32)
            .collect::<Vec<_>>(),
    );
    let mut rng = Rng::new(3 + rank as u64);
    let mut moved = 0;
    for round in 0..41 {
        if round > 0 {
            let sway = if round % 2 == 0 { 0.4 } else { -0.4 };
            for x in &mut mine.position {
                x[0] = (x[0] + sway * rng.next()).clamp(0.0, 2.0);
            }
        }
        let traffic = migrate(&world, &d, &mut mine).unwrap_or_else(|e| fail(rank, e.to_string()));
        moved += traffic.sent;
        if (0..mine.len()).any(|k| d.owner(&mine.position[k]) != rank) {
            fail(
                rank,
                format!("round {round}: a particle not owned after migration"),
            );
        }
        let total = world
            .sum(&[mine.len() as f64])
            .unwrap_or_else(|e| fail(rank, e.to_string()))[0];
        if total != N as f64 {
            fail(
                rank,
                format!("round {round}: {total} particles in all, {N} expected"),
            );
        }
    }
    // Every id once: the ids gathered as f64 (exact below 2^53).
    let ids: Vec<f64> = mine.id.iter().map(|&i| i as f64).collect();
    let mut counts = vec![0.0; size];
    counts[rank] = ids.len() as f64;
    let counts = world.sum(&counts).unwrap_or_else(|e| fail(rank, e.to_string()));
    let longest = counts.iter().cloned().fold(0.0, f64::max) as usize;
    let mut padded = ids.clone();
    padded.resize(longest, -1.0);
    let gathered = world
        .all_gather(&padded)
        .unwrap_or_else(|e| fail(rank, e.to_string()));
    let mut seen: Vec<u32> = gathered
        .iter()
        .flatten()
        .filter(|&&i| i >= 0.0)
        .map(|&i| i as u32)
        .collect();
    seen.sort_unstable();
    if seen != (0..N as u32).collect::<Vec<_>>() {
        fail(rank, "ids lost or duplicated".into());
    }
    // Unmoved fields keep their bits (positions moved by the sway, so compare the rest).
    for k in 0..mine.len() {
        let original = signature(&all, mine.id[k] as usize);
        if signature(&mine, k)[2..] != original[2..] {
            fail(rank, format!("particle {} changed in transit", mine.id[k]));
        }
    }
    let (ghosts, halo) =
        gather_ghosts(&world, &d, &mine, WIDTH).unwrap_or_else(|e| fail(rank, e.to_string()));
    // Every neighbour of an owned particle among all ranks' particles is owned or a ghost here.
    let positions: Vec<f64> = mine
        .position
        .iter()
        .flat_map(|x| [x[0] as f64, x[1] as f64])
        .collect();
    let mut padded = positions;
    padded.resize(2 * longest, f64::NAN);
    let everyone = world
        .all_gather(&padded)
        .unwrap_or_else(|e| fail(rank, e.to_string()));
    let here: Vec<Vector<2>> = mine.position.iter().chain(&ghosts.position).copied().collect();
    for p in everyone.iter().flat_map(|v| v.chunks_exact(2)) {
        if p[0].is_nan() {
            continue;
        }
        let q = Vector::<2>::new(p[0] as f32, p[1] as f32);
        let near = mine.position.iter().any(|x| (x - q).norm() < WIDTH);
        if near && !here.contains(&q) {
            fail(rank, format!("neighbour at {q:?} missing from the halo"));
        }
    }
    let bytes = world
        .sum(&[halo.bytes_sent as f64])
        .unwrap_or_else(|e| fail(rank, e.to_string()))[0];
    if rank == 0 {
        println!(
            "mpi_exchange: {size} ranks, {N} particles, {moved} moved by rank 0 over 40 rounds, halo {bytes} bytes in all: ok"
        );
    }
}
