/* Benchmark driver of rollslide's batch kernels (run by `cargo bench --bench batch`).
 *
 * Usage: bench_driver [CONTACTS [REPS]] [--workload=A|B] [--slip=F] [--only=SUBSTRING]
 *                     [--set=NAME] [--level=auto|scalar|avx2|avx512]
 *   CONTACTS  number of contacts (default 1200000); REPS timed calls per row (default 5; the
 *             row's number is the fastest call). --workload: A (default) or B, below.
 *             --slip: fraction of the contacts that start beyond each law's limit (default
 *             0.25; see Histories). --only: measure only the rows whose name contains
 *             SUBSTRING, or only the row NAME with --only='NAME$' (the baselines and floors
 *             always run; for profiling). --set: only the physics set NAME (full, rolltwist
 *             or sliding, below), or --set=wall for the group wall alone (below). --level:
 *             the SIMD level of the rows that otherwise run at the best one (history_,
 *             indexed_, contacts_, decompose_; default auto), e.g. to time the
 *             contact-major call of an AVX2 host on an AVX-512 one.
 *
 * Workloads (both: particle radii 0.49-0.50, centres jittered by +-1e-3, every listed contact
 * overlapping by 0.007-0.033, normal force k_n * overlap):
 *   A  (headline) particles spatially sorted as a DEM code keeps them: a jittered FCC packing
 *      (nearest-neighbour distance 0.97, 12 neighbours per particle, ~6 contacts per particle
 *      counted once), particle ids in the order of LAMMPS' atom sort: lexicographic order of
 *      spatial bins of half the neighbour cutoff (cutoff = largest diameter + skin 0.1, so bins
 *      of 0.55), x fastest, then y, then z (`ibin = (iz*nbiny + iy)*nbinx + ix`, Atom::sort),
 *      ties in lattice order. Contacts in half-neighbour-list order: each pair once, body 1 the
 *      lower id, sorted by body 1 then body 2. Body 2 is then at most about one lattice plane
 *      (~2 n^2 ids) ahead of body 1: it comes from a window that stays in L2.
 *   B  the previous workload: a jittered cubic packing (6 face neighbours per particle),
 *      particle ids RANDOMLY PERMUTED and contacts sorted by body 1, so body 2 (and its force
 *      and torque) is a random memory access: a well-mixed packing never re-sorted.
 * If the packing has more contacts than CONTACTS, the list is cut after the first CONTACTS (in
 * contact order), so the last particles have fewer contacts.
 *
 * Histories (both workloads; persistent, non-zero, so transport and clip do real work):
 * previous normals tilted ~1e-3 rad from the current normal; sliding and rolling springs
 * tangent to the previous normal, in random directions. For each law independently, a random
 * quarter (--slip) of the contacts starts beyond its limit: k |spring| = m * limit with m in
 * [1.05, 2) (the step clips them), the others m in [0.05, 0.95) (sliding: k_t |xi_s| against
 * mu f_n; rolling: k_r |xi_r| against mu_r f_n; twisting: k_tw |theta| against mu_tw f_n,
 * random sign). Which contacts slip is random, not periodic in c, so a scalar loop's clip
 * branches are mispredicted about as often as they are taken (out of cache; in cache the
 * predictor partly learns the repeated sequence): the hand-written baselines pay for that and
 * the SIMD kernels (selects) do not, so the baseline ratios depend on --slip. Hence the
 * [noslip] rows: the same springs with those beyond a limit scaled below it (no clip taken,
 * the baselines' best case). (The previous driver scaled the springs by 2 on c = 0 mod 4,
 * which put ~5.5% of the contacts at the sliding limit, in a pattern of period 4, and none at
 * the rolling or twisting limit.) "info" lines give the measured fraction of contacts at each
 * limit. Each timed call starts from the same copy of the states and zeroed accumulators
 * (restored untimed).
 *
 * Physics sets (each compared with its own hand-written baseline; the library model is the
 * LAMMPS_2021 preset with the laws below; parameters KT..MUTW):
 *   full       linear-history sliding + rolling sds (EPSD, given k_r, gamma_r, mu_r) +
 *              twisting sds
 *   rolltwist  rolling sds + twisting sds, sliding law RSL_SLIDING_NONE. Force on body 1 is
 *              -f_n n; torques only from rolling and twisting; the sliding spring is left as it
 *              was.
 *   sliding    linear-history sliding only
 *
 * Wall group (group wall, workload A only, after the three sets): sphere-wall contacts with the
 * full set's physics and model (LAMMPS_2021: sliding linear + rolling sds + twisting sds).
 * Every particle of workload A's scene (the sorted particles, in id order) touches one flat
 * wall of its own, contact c = particle c (a host looping over its particles, as LAMMPS' fix
 * wall/gran does; one sphere-wall contact per particle, so the group has as many contacts as
 * particles, about a sixth of CONTACTS). Each wall is a plane below its particle: its outward
 * unit normal +z (half of the walls, at random) or one fixed tilted unit vector (the other
 * half; its length computes to exactly 1, so the library's normalisation returns its bits),
 * its point at the particle's centre less (R - delta) along the normal plus a random
 * tangential offset, delta drawn in [0.007, 0.033) as the pair overlaps are; all walls move
 * with the same small velocity (0.02, -0.01, 0.005) and zero angular velocity (rsl_wall, 96 B
 * per contact). f_n = k_n * overlap, the overlap R - h as the library computes it. Histories as
 * the pairs' (persistent, previous normal tilted ~1e-3 rad from n = -wall normal, sliding and
 * rolling springs tangent to it, a random --slip fraction beyond each limit, drawn from a
 * generator seeded for the group, so the walls are the same whatever ran before). No
 * [noslip] rows.
 *
 * Rows (one output line each: "row GROUP NAME NS_PER_CONTACT LOADS_DIFF STATE_DIFF FLAGS"). The
 * rows of a physics set (GROUP) are measured together, after their floor and baseline, so
 * that the same-run ratios compare measurements taken close in time:
 *   floor_plain     streams the bytes the particle-major batch call touches, with its access
 *                   pattern, no physics: reads pairs[c], f_n[c], both particles (80 B each),
 *                   reads and writes the 112-byte state, read-modify-writes force and torque
 *                   of both particles (24 B each). The batch kernel reads and writes the whole
 *                   state whatever the laws (src/batch/mod.rs step_kernel), so the bytes are
 *                   the same for every physics set; it is re-measured for each set.
 *   floor_prefetch  the same loop with software prefetches of the scattered lines 48 contacts
 *                   ahead, as the library's batch kernel does (helps workload B)
 *   floor           the faster of the two (the floor the ratios use)
 *   baseline_c_plain  hand-written C, inline, one loop, LAMMPS style (n = d * (1/r), full-radii
 *                   sliding velocity, project-rescale transport with LAMMPS' 1e-10 threshold,
 *                   LAMMPS' clip), the set's physics; reads and writes the library's state
 *                   struct so its states can be compared. Built with -std=c11, so GCC does not
 *                   contract a*b+c into FMAs (nor does rustc): the f64 library rows usually
 *                   agree with it bit for bit (diff 0); -ffp-contract=fast changed the
 *                   baseline's time by less than the run-to-run scatter when tried.
 *   baseline_c_prefetch  the same loop with the library's prefetches, 48 contacts ahead (as
 *                   floor_prefetch), so that no baseline waits on memory the library prefetches
 *   baseline_c      the faster of the two: the baseline every ratio uses
 *   percontact_acc_c  rsl_contact_step_accumulate per contact (the library adds the loads)
 *   percontact_c    rsl_contact_step per contact + the host adds the loads
 *   percontact_fill_c  rsl_contact_step_accumulate per contact from a host whose particles
 *                   are in its own arrays (x, v, omega, radius apart, as in LAMMPS): it fills
 *                   two rsl_sphere structs on its stack just before each call
 *   percontact_fill64_c  the same host, filling the sphere pairs of 64 contacts into a small
 *                   buffer first, then calling for each (the stores are done long before the
 *                   library reads them: see docs/batch.md, "Filling the structs")
 *   percontact_params_c  rsl_contact_step_accumulate per contact with the sliding stiffness
 *                   and damping passed per contact, as a Hertz-Mindlin host does (its k_t and
 *                   gamma_t depend on the overlap): in.flags = RSL_INPUT_SLIDING_STIFFNESS |
 *                   RSL_INPUT_SLIDING_DAMPING, in.sliding_stiffness and in.sliding_damping read
 *                   from two per-contact arrays (scene kt, gt) holding the model's own KT and
 *                   the set's gamma_t (GT), so the physics is the baseline's (compared: diff 0
 *                   expected). Groups with a sliding law only (full, sliding)
 *   percontact_acc_unchecked_c, percontact_params_unchecked_c  the same two rows through
 *                   rsl_contact_step_accumulate_unchecked (the step without the tests of the
 *                   values, for hosts that validated their data)
 *   batch_<p>_<l>   rsl_batch_step (particle-major), precision p = f64|f32, SIMD level
 *                   l = scalar|avx2|avx512 (each level rsl_batch_simd_support reports)
 *   history_<p>_<l>  rsl_batch_step_history (particle-major, packed histories of
 *                   rsl_model_history_size doubles, packed from the states untimed) at the
 *                   best level (or --level's); the records are unpacked into the states for
 *                   the diff (the fields a record does not keep, and the slip flags, taken
 *                   from the baseline)
 *   indexed_<p>_<l>  rsl_batch_step_indexed (particle-major, each contact's state in place
 *                   in an array of one state per neighbour-list entry, 1.5 nc entries, every
 *                   third entry a pair not in contact: see IST) at the best level (or
 *                   --level's); the states copied back in contact order (untimed) for the diff
 *   floor_indexed_plain, floor_indexed_prefetch, floor_indexed,
 *   baseline_c_indexed_plain, baseline_c_indexed_prefetch, baseline_c_indexed  the set's
 *                   floors and hand-written loops (without and with the prefetches, and the
 *                   faster of each) on the indexed rows' layout, contact c's state at
 *                   IST[IDX[c]]: the floor and baseline of the indexed_* rows (run with
 *                   the first of them)
 *   contacts_<p>_<l>  rsl_batch_step_contacts (contact-major) at the best level (RSL_SIMD_AUTO,
 *                   or --level's; l is the level that ran); bodies pre-gathered per contact
 *                   (untimed); its loads are added to the accumulators after the call
 *                   (untimed) for the diff
 *   decompose_<p>_<l>  rsl_batch_decompose (particle-major) at the best level (or --level's):
 *                   the kinematic decomposition only, no laws, no state (group full; not the
 *                   baseline's work)
 *   <row>[noslip]   the baselines, percontact_acc_c, percontact_params_c (groups full and
 *                   sliding) and batch_<p>_<auto level> again on the no-slip histories (the
 *                   same springs, those beyond a limit scaled below it: no clip taken, the
 *                   scalar baselines' best case); compared with baseline_c[noslip]
 *   batch_f64_<l>[LAWS]  workload A only: rsl_batch_step of other law sets at each level, f64
 *                   (every model runs the same kernel, which takes its law decisions at run
 *                   time): full/exact, slide+roll/exact, slide+roll/lammps,
 *                   full/lammps+marshall (twisting marshall), full/exact+marshall,
 *                   slide+twist/lammps (no rolling law), slide+twist/exact, slide+cdt/liggghts
 *                   (LIGGGHTS_3_8 preset: linear sliding + cdt rolling on k_n delta, k_n passed
 *                   per contact), slide+epsd2/liggghts (LIGGGHTS_3_8 preset: linear sliding +
 *                   EPSD rolling with LIGGGHTS' epsd2 stiffness k_t R^2, the length form, no
 *                   rolling dashpot) (group full),
 *                   roll+twist/exact, roll/exact, roll/lammps (rolling only: no twisting law),
 *                   twist/lammps (twisting only: no sliding or rolling law), twist/exact
 *                   (group rolltwist),
 *                   sliding/exact (group sliding).
 *                   The exact sets are the OBJECTIVE preset (exact rotation transport,
 *                   midplane branches). None is the baseline's physics: their rows are not
 *                   compared ("-"), the ratios give their cost only.
 *   percontact_acc_c[LAWS]  workload A only: rsl_contact_step_accumulate per contact on the
 *                   model of each of those law sets, k_n passed per contact.
 *   materials<N>_f64_<l>  group full, both workloads, each level: mixed materials, the full
 *                   set's contacts through rsl_batch_step_params with a table of N = 1, 3 or 10
 *                   coefficient sets (rsl_model_set_materials) and each contact's index into it
 *                   (rsl_batch_contact_params.material), as a host with 1, 2 or 4 atom types
 *                   and one set per unordered type pair (LAMMPS' pair_coeff) steps them: each
 *                   particle gets a random type, a contact the set of its two types' pair, so
 *                   the sets interleave along the contact list ("info materials<N>" gives the
 *                   fraction of contacts per set). Set 0 is the full set's own model; the
 *                   others scale each of its nine coefficients (k_t, gamma_t, mu, k_r, gamma_r,
 *                   mu_r, k_tw, gamma_tw, mu_tw) by a factor in [0.5, 2) ("info materials"
 *                   lists them; set k is the same in every table). materials1 has the
 *                   baseline's physics (compared: diff 0 expected); materials3 and materials10
 *                   do not (not compared, "-"): set against materials1 and batch_f64_<l> they
 *                   give the cost of the per-contact coefficients.
 * Rows of the group wall (the sphere-wall contacts above; ratios against baseline_wall_c and
 * floor_wall):
 *   floor_wall      streams the bytes the per-contact wall call touches, in contact order, no
 *                   physics: reads the particle (80 B), f_n[c] and the wall (96 B: point,
 *                   normal, velocity, angular velocity), reads and writes the 112-byte state,
 *                   read-modify-writes the particle's force and torque (24 B each). Every
 *                   access is sequential (no prefetch variant: the hardware prefetchers see it;
 *                   the batch_wall rows also read spheres[c], 4 B)
 *   baseline_wall_c  hand-written C, inline, one loop, LAMMPS style (as baseline_c: LAMMPS'
 *                   project-rescale transport with its 1e-10 threshold and its clip, the same
 *                   lammps_spring and lammps_twist), the full set's physics for a wall as the
 *                   LAMMPS_2021 preset steps it (src/laws/step.rs, the Partner::Wall arms):
 *                   n = -wall normal (the wall normal used as it is: unit), h = (x - point) .
 *                   wall normal, overlap R - h, midplane branch l1 = R - overlap/2 (the torque
 *                   arm of n x F_t, as LAMMPS' dist_to_contact), rolling radius R (R_eff of a
 *                   flat wall), sliding velocity with the full radius as arm (the preset's
 *                   sliding rate; its branch rule stays midplane), written in the library's
 *                   order: (v + (w x n) l1 - v_wall)_t + (w x n)(R - l1) (LAMMPS' own
 *                   (v - v_wall)_t + R (w x n) is the same quantity with other roundings, and
 *                   the same cost to within a multiply-add); rolling rate R (w x n),
 *                   twisting rate w . n. The wall's angular velocity is zero
 *                   and the baseline (a translating wall, as LAMMPS' fix wall/gran) does not
 *                   read it. Its double results equal the library's bit for bit (diff 0).
 *   percontact_wall_unchecked_c  the same through rsl_contact_step_wall_accumulate_unchecked
 *                   (no test of the values)
 *   percontact_wall_c  rsl_contact_step_wall_accumulate per contact (the library adds the
 *                   sphere's loads to its force and torque)
 *   batch_wall_<p>_<l>_c  rsl_batch_step_walls over the whole scene in one call (spheres[c] = c,
 *                   states in contact order: state_index NULL; params and normal_stiffness
 *                   NULL: the model's k_t and gamma_t, as percontact_wall_c's input sets no
 *                   flag), precision p = f64|f32, SIMD level l = scalar|avx2|avx512 (each
 *                   level rsl_batch_simd_support reports), as the batch_<p>_<l> rows of the
 *                   pair groups (benches/batch.rs sets each against group full's of the same
 *                   p and l, per contact). The f64 results equal baseline_wall_c's bit for bit
 *                   (diff 0); the f32 diffs are their rounding.
 * LOADS_DIFF: max |difference| of the accumulated forces and torques from the set's baseline,
 * relative to the largest baseline force (torque) component; STATE_DIFF: the same for the
 * springs, twisting angle and normal of the states after the call; FLAGS: number of contacts
 * whose slip flags differ from the baseline's. "-": not compared (floors; other physics).
 * "info" lines describe the run (workload, sizes, SIMD levels, fractions at each limit).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rollslide.h"

typedef struct {
    size_t np, nc;
    rsl_sphere *p;
    uint32_t *pairs;
    double *fn;
    double *kn; /* k_n per contact (KN), read only by the models that need it (LIGGGHTS' cdt) */
    rsl_contact_state *st0, *st;
    rsl_contact_state *st0_slip, *st0_noslip; /* st0 points to one of them */
    rsl_vec3 *f, *t;
    rsl_sphere *b1, *b2; /* pre-gathered for the contact-major calls */
    rsl_batch_loads *loads;
    rsl_decomposition *dec;
    /* The particles as a host keeps them in its own layout (LAMMPS: x, v, omega, radius in
     * separate arrays), for the percontact_fill rows; NULL elsewhere. */
    double *hx, *hv, *hw, *hr;
    /* Per-contact sliding stiffness and damping of the percontact_params rows (KT and GT). */
    double *kt, *gt;
    /* The group wall's scene: each contact's wall and sphere (contact c is particle c:
     * spheres[c] = c, for rsl_batch_step_walls); NULL elsewhere. */
    rsl_wall *walls;
    uint32_t *spheres;
} scene;

static uint64_t rng_state = 12345;
static double urand(void) {
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *xmalloc(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "out of memory (%zu bytes)\n", n);
        exit(1);
    }
    return p;
}

static void *xcalloc(size_t n, size_t size) {
    void *p = calloc(n ? n : 1, size);
    if (!p) {
        fprintf(stderr, "out of memory (%zu x %zu bytes)\n", n, size);
        exit(1);
    }
    return p;
}

/* Contacts sorted by body 1 (workload B: the order within a body 1 is whatever qsort gives). */
static int cmp_body1(const void *a, const void *b) {
    const uint32_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Contacts sorted by body 1, then body 2 (workload A: half neighbour list). */
static int cmp_pair(const void *a, const void *b) {
    const uint32_t *x = a, *y = b;
    if (x[0] != y[0]) return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* Model parameters shared by the library models and the baselines. */
static const double KT = 2.0e5, GT = 30.0, MU = 0.5;
static const double KR = 1.0e5, GR = 10.0, MUR = 0.1;
static const double KTW = 50.0, GTW = 0.5, MUTW = 0.05;
static const double KN = 1.0e6, DT = 1.0e-5;

static void random_motion(rsl_sphere *q) {
    q->velocity.x = 0.1 * (urand() - 0.5);
    q->velocity.y = 0.1 * (urand() - 0.5);
    q->velocity.z = 0.1 * (urand() - 0.5);
    q->angular_velocity.x = 2 * (urand() - 0.5);
    q->angular_velocity.y = 2 * (urand() - 0.5);
    q->angular_velocity.z = 2 * (urand() - 0.5);
    q->radius = 0.5 - 0.01 * urand();
}

/* ---- workload B: jittered cubic packing, ids randomly permuted ---- */
static void build_cubic_permuted(scene *s, size_t nc_target) {
    /* the smallest cube with at least nc_target face contacts (3 side^2 (side - 1)) */
    size_t side = 2;
    while (3 * side * side * (side - 1) < nc_target) side++;
    size_t np = side * side * side;
    size_t *perm = xmalloc(np * sizeof *perm);
    for (size_t i = 0; i < np; i++) perm[i] = i;
    for (size_t i = np - 1; i > 0; i--) {
        size_t j = (size_t)(urand() * (double)(i + 1));
        size_t tmp = perm[i];
        perm[i] = perm[j];
        perm[j] = tmp;
    }
    s->np = np;
    s->p = xcalloc(np, sizeof *s->p);
    const double a = 0.97;
    for (size_t x = 0; x < side; x++)
        for (size_t y = 0; y < side; y++)
            for (size_t z = 0; z < side; z++) {
                rsl_sphere *q = &s->p[perm[(x * side + y) * side + z]];
                q->position.x = a * (double)x + 2e-3 * (urand() - 0.5);
                q->position.y = a * (double)y + 2e-3 * (urand() - 0.5);
                q->position.z = a * (double)z + 2e-3 * (urand() - 0.5);
                random_motion(q);
            }
    uint32_t *pairs = xmalloc(3 * np * 2 * sizeof *pairs);
    size_t nc = 0;
    for (size_t x = 0; x < side; x++)
        for (size_t y = 0; y < side; y++)
            for (size_t z = 0; z < side; z++) {
                size_t i = perm[(x * side + y) * side + z];
                size_t nb[3][3] = {{x + 1, y, z}, {x, y + 1, z}, {x, y, z + 1}};
                for (int k = 0; k < 3 && nc < nc_target; k++) {
                    if (nb[k][0] >= side || nb[k][1] >= side || nb[k][2] >= side) continue;
                    pairs[2 * nc] = (uint32_t)i;
                    pairs[2 * nc + 1] =
                        (uint32_t)perm[(nb[k][0] * side + nb[k][1]) * side + nb[k][2]];
                    nc++;
                }
            }
    qsort(pairs, nc, 2 * sizeof(uint32_t), cmp_body1);
    s->nc = nc;
    s->pairs = pairs;
    free(perm);
}

/* ---- workload A: jittered FCC packing, ids in LAMMPS atom-sort order ---- */

/* Lattice sites (i, j, k), 0 <= i, j, k < 2 n, i + j + k even (n^3 cubic cells, 4 n^3 sites),
 * at (i, j, k) * H; nearest neighbours at the 12 offsets (+-1, +-1, 0) and permutations. */
static const int FCC_NB[12][3] = {{1, 1, 0},  {1, -1, 0},  {-1, 1, 0}, {-1, -1, 0},
                                  {1, 0, 1},  {1, 0, -1},  {-1, 0, 1}, {-1, 0, -1},
                                  {0, 1, 1},  {0, 1, -1},  {0, -1, 1}, {0, -1, -1}};

static size_t fcc_pair_count(size_t n) {
    long L = 2 * (long)n;
    size_t count = 0;
    for (long i = 0; i < L; i++)
        for (long j = 0; j < L; j++)
            for (long k = (i + j) % 2; k < L; k += 2)
                for (int o = 0; o < 12; o++) {
                    long a = i + FCC_NB[o][0], b = j + FCC_NB[o][1], c = k + FCC_NB[o][2];
                    if (a >= 0 && b >= 0 && c >= 0 && a < L && b < L && c < L) count++;
                }
    return count / 2;
}

typedef struct {
    uint64_t key; /* LAMMPS sort bin */
    uint32_t site; /* creation (lattice) order: the tie break */
} sort_key;

static int cmp_key(const void *a, const void *b) {
    const sort_key *x = a, *y = b;
    if (x->key != y->key) return (x->key > y->key) - (x->key < y->key);
    return (x->site > y->site) - (x->site < y->site);
}

static void build_fcc_sorted(scene *s, size_t nc_target) {
    const double H = 0.97 / sqrt(2.0); /* half the cubic lattice constant */
    size_t n = 1;
    while (fcc_pair_count(n) < nc_target) n++;
    long L = 2 * (long)n;
    size_t np = 4 * n * n * n;
    /* sites in creation order, with their lattice coordinates */
    rsl_sphere *tmp = xcalloc(np, sizeof *tmp);
    long *coord = xmalloc(3 * np * sizeof *coord);
    int32_t *site_of = xmalloc((size_t)(L * L * L) * sizeof *site_of);
    size_t q = 0;
    for (long i = 0; i < L; i++)
        for (long j = 0; j < L; j++)
            for (long k = 0; k < L; k++) {
                if ((i + j + k) % 2) {
                    site_of[(i * L + j) * L + k] = -1;
                    continue;
                }
                rsl_sphere *p = &tmp[q];
                p->position.x = H * (double)i + 2e-3 * (urand() - 0.5);
                p->position.y = H * (double)j + 2e-3 * (urand() - 0.5);
                p->position.z = H * (double)k + 2e-3 * (urand() - 0.5);
                random_motion(p);
                coord[3 * q] = i, coord[3 * q + 1] = j, coord[3 * q + 2] = k;
                site_of[(i * L + j) * L + k] = (int32_t)q;
                q++;
            }
    /* LAMMPS Atom::sort: bins of half the neighbour cutoff over the bounding box,
     * ibin = (iz * nbiny + iy) * nbinx + ix */
    const double cutoff = 2 * 0.5 + 0.1, bin = 0.5 * cutoff;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t a = 0; a < np; a++) {
        const double *x = &tmp[a].position.x;
        for (int d = 0; d < 3; d++) lo[d] = fmin(lo[d], x[d]), hi[d] = fmax(hi[d], x[d]);
    }
    uint64_t nb[3];
    for (int d = 0; d < 3; d++) nb[d] = (uint64_t)((hi[d] - lo[d]) / bin) + 1;
    sort_key *keys = xmalloc(np * sizeof *keys);
    for (size_t a = 0; a < np; a++) {
        const double *x = &tmp[a].position.x;
        uint64_t ib[3];
        for (int d = 0; d < 3; d++) {
            ib[d] = (uint64_t)((x[d] - lo[d]) / bin);
            if (ib[d] >= nb[d]) ib[d] = nb[d] - 1;
        }
        keys[a].key = (ib[2] * nb[1] + ib[1]) * nb[0] + ib[0];
        keys[a].site = (uint32_t)a;
    }
    qsort(keys, np, sizeof *keys, cmp_key);
    uint32_t *id = xmalloc(np * sizeof *id);
    s->np = np;
    s->p = xcalloc(np, sizeof *s->p);
    for (size_t r = 0; r < np; r++) {
        id[keys[r].site] = (uint32_t)r;
        s->p[r] = tmp[keys[r].site];
    }
    /* half neighbour list: each nearest-neighbour pair once, body 1 the lower id */
    uint32_t *pairs = xmalloc(12 * np * sizeof *pairs);
    size_t nc = 0;
    for (size_t a = 0; a < np; a++)
        for (int o = 0; o < 12; o++) {
            long i = coord[3 * a] + FCC_NB[o][0], j = coord[3 * a + 1] + FCC_NB[o][1],
                 k = coord[3 * a + 2] + FCC_NB[o][2];
            if (i < 0 || j < 0 || k < 0 || i >= L || j >= L || k >= L) continue;
            uint32_t other = id[site_of[(i * L + j) * L + k]];
            if (id[a] < other) {
                pairs[2 * nc] = id[a];
                pairs[2 * nc + 1] = other;
                nc++;
            }
        }
    qsort(pairs, nc, 2 * sizeof(uint32_t), cmp_pair);
    if (nc > nc_target) nc = nc_target;
    s->nc = nc;
    s->pairs = pairs;
    free(tmp);
    free(coord);
    free(site_of);
    free(keys);
    free(id);
}

/* A spring length as a multiple of (limit / stiffness): beyond the limit (1.05 to 2) for a
 * random fraction SLIP of the contacts, below it (0.05 to 0.95) otherwise. The dashpot and the
 * step's increment change the load by far less than the 5% margins, so exactly these contacts
 * clip, in an order no branch predictor learns. */
static double SLIP = 0.25; /* --slip=F: the fraction of contacts beyond each limit */
static double limit_multiple(void) {
    return urand() < SLIP ? 1.05 + 0.95 * urand() : 0.05 + 0.9 * urand();
}

/* A random unit vector tangent to the unit normal n. */
static void random_tangent(double nx, double ny, double nz, double t[3]) {
    for (;;) {
        double u[3] = {urand() - 0.5, urand() - 0.5, urand() - 0.5};
        double un = u[0] * nx + u[1] * ny + u[2] * nz;
        for (int k = 0; k < 3; k++) u[k] -= un * (k == 0 ? nx : k == 1 ? ny : nz);
        double m = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (m > 1e-3) {
            for (int k = 0; k < 3; k++) t[k] = u[k] / m;
            return;
        }
    }
}

/* Per-contact arrays, normal forces and the persistent histories (both workloads). */
static void finish(scene *s) {
    size_t nc = s->nc, np = s->np;
    const uint32_t *pairs = s->pairs;
    s->fn = xmalloc(nc * sizeof(double));
    s->kn = xmalloc(nc * sizeof(double));
    s->kt = xmalloc(nc * sizeof(double));
    s->gt = xmalloc(nc * sizeof(double));
    s->st0_slip = xcalloc(nc, sizeof *s->st0_slip);
    s->st0_noslip = xcalloc(nc, sizeof *s->st0_noslip);
    s->st0 = s->st0_slip;
    s->st = xcalloc(nc, sizeof *s->st);
    s->b1 = xmalloc(nc * sizeof *s->b1);
    s->b2 = xmalloc(nc * sizeof *s->b2);
    /* written once here so that no timed call pays the first-touch page faults */
    s->loads = xmalloc(nc * sizeof *s->loads);
    s->dec = xmalloc(nc * sizeof *s->dec);
    memset(s->loads, 0, nc * sizeof *s->loads);
    memset(s->dec, 0, nc * sizeof *s->dec);
    for (size_t c = 0; c < nc; c++) {
        const rsl_sphere *p1 = &s->p[pairs[2 * c]], *p2 = &s->p[pairs[2 * c + 1]];
        double dx = p2->position.x - p1->position.x, dy = p2->position.y - p1->position.y,
               dz = p2->position.z - p1->position.z;
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        double fn = KN * (p1->radius + p2->radius - d);
        if (!(fn > 0)) {
            fprintf(stderr, "contact %zu does not overlap\n", c);
            exit(1);
        }
        s->fn[c] = fn;
        s->kn[c] = KN;
        s->kt[c] = KT;
        s->gt[c] = GT;
        s->b1[c] = *p1;
        s->b2[c] = *p2;
        /* previous normal tilted by ~1e-3; springs tangent to it */
        double nx = dx / d + 1e-3 * (urand() - 0.5), ny = dy / d + 1e-3 * (urand() - 0.5),
               nz = dz / d + 1e-3 * (urand() - 0.5);
        double nn = sqrt(nx * nx + ny * ny + nz * nz);
        nx /= nn, ny /= nn, nz /= nn;
        rsl_contact_state *st = &s->st0_slip[c];
        double ts[3], tr[3];
        random_tangent(nx, ny, nz, ts);
        random_tangent(nx, ny, nz, tr);
        double ms = limit_multiple(), mr = limit_multiple(), mtw = limit_multiple();
        double sign = urand() < 0.5 ? -1.0 : 1.0;
        /* the no-slip companion: the same springs, those beyond a limit brought below it */
        rsl_contact_state *quiet = &s->st0_noslip[c];
        for (int k = 0; k < 2; k++, st = quiet) {
            double f = k == 0 ? 1.0 : 0.47; /* [1.05, 2) -> [0.49, 0.94) */
            double ks = (ms < 1 ? 1.0 : f) * ms * MU * fn / KT;
            double kr = (mr < 1 ? 1.0 : f) * mr * MUR * fn / KR;
            st->previous_normal.x = nx, st->previous_normal.y = ny, st->previous_normal.z = nz;
            st->sliding_spring.x = ks * ts[0], st->sliding_spring.y = ks * ts[1];
            st->sliding_spring.z = ks * ts[2];
            st->rolling_spring.x = kr * tr[0], st->rolling_spring.y = kr * tr[1];
            st->rolling_spring.z = kr * tr[2];
            st->twisting_angle = sign * (mtw < 1 ? 1.0 : f) * mtw * MUTW * fn / KTW;
        }
    }
    s->f = xcalloc(np, sizeof *s->f);
    s->t = xcalloc(np, sizeof *s->t);
}

static rsl_model *MODEL; /* the model of the current measurement */
enum { PARTICLE_MAJOR, CONTACT_MAJOR, DECOMPOSE, HISTORY, INDEXED, MATERIALS, WALLS };
static int MODE;
/* Packed histories of the history_* rows (rsl_batch_step_history): HWORDS doubles per contact,
 * room for 13. */
static double *HIST;
static size_t HWORDS;
/* States of the indexed_* rows (rsl_batch_step_indexed), one per neighbour-list entry as
 * LAMMPS' granular pair styles keep them: a list of NSTATES = 3 nc / 2 entries (rounded up)
 * of which contact c's is entry IDX[c] = c + c / 2, so that one entry in three (the third of
 * each run of three) is a pair not in contact, whose state is not read or written. */
static rsl_contact_state *IST;
static size_t *IDX, NSTATES;

static void reset(scene *s) {
    memcpy(s->st, s->st0, s->nc * sizeof *s->st);
    if (MODE == INDEXED)
        for (size_t c = 0; c < s->nc; c++) IST[IDX[c]] = s->st0[c];
    if (MODE == HISTORY)
        for (size_t c = 0; c < s->nc; c++)
            if (rsl_history_from_state(MODEL, &s->st0[c], HIST + c * HWORDS) != RSL_OK) exit(1);
    memset(s->f, 0, s->np * sizeof *s->f);
    memset(s->t, 0, s->np * sizeof *s->t);
}

/* ---- hand-written LAMMPS-style baselines (the physics of the LAMMPS_2021 preset) ---- */

#define DOT(a, b) ((a)[0] * (b)[0] + (a)[1] * (b)[1] + (a)[2] * (b)[2])
#define CROSS(o, a, b)                              \
    do {                                            \
        (o)[0] = (a)[1] * (b)[2] - (a)[2] * (b)[1]; \
        (o)[1] = (a)[2] * (b)[0] - (a)[0] * (b)[2]; \
        (o)[2] = (a)[0] * (b)[1] - (a)[1] * (b)[0]; \
    } while (0)

/* LAMMPS project-rescale of a history vector, its threshold rule, then the spring step with
 * LAMMPS' clip (zero-length slipping spring gives no load). */
static inline void lammps_spring(double xi[3], const double n[3], const double rate[3], double k,
                                 double gamma, double limit, double load[3], uint32_t *slipped) {
    double xn = DOT(xi, n);
    double thr = k > 0 ? 1e-10 * limit / k : 0.0;
    double old2 = DOT(xi, xi);
    double p[3] = {xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]};
    double new2 = DOT(p, p);
    if (fabs(xn) > thr && new2 > 0) {
        double sc = sqrt(old2 / new2);
        xi[0] = p[0] * sc, xi[1] = p[1] * sc, xi[2] = p[2] * sc;
    }
    for (int a = 0; a < 3; a++) xi[a] += rate[a] * DT;
    double f[3];
    for (int a = 0; a < 3; a++) f[a] = -k * xi[a] - gamma * rate[a];
    double mag = sqrt(DOT(f, f));
    *slipped = mag > limit;
    if (mag > limit) {
        if (DOT(xi, xi) <= 0) {
            f[0] = f[1] = f[2] = 0;
        } else {
            double sc = limit / mag;
            for (int a = 0; a < 3; a++) {
                f[a] *= sc;
                if (k > 0) xi[a] = (-1.0 / k) * (f[a] + gamma * rate[a]); /* as LAMMPS */
            }
        }
    }
    load[0] = f[0], load[1] = f[1], load[2] = f[2];
}

/* LAMMPS twisting sds: returns the twisting moment on body 1 along n, updates the angle. */
static inline double lammps_twist(double *theta, double wtw, double fn, uint32_t *slipped) {
    double th = *theta + wtw * DT;
    double mt = -KTW * th - GTW * wtw;
    double lim = MUTW * fn;
    *slipped = fabs(mt) > lim;
    if (*slipped) {
        mt = wtw > 0 ? -lim : (wtw < 0 ? lim : 0.0);
        th = (1.0 / KTW) * -(mt + GTW * wtw); /* as LAMMPS */
    }
    *theta = th;
    return mt;
}

/* The lines of contact e that the library's batch kernel prefetches (src/capi/batch.rs: PREFETCHT1
 * of each scattered slot's first and last word and of the state; here the lines written get
 * PREFETCHW where -march has it), AHEAD contacts before it needs them. The prefetching
 * baselines and floor call it for c + AHEAD. */
#define AHEAD 48
/* always_inline: without it GCC 12 emitted none of these prefetches (it seems to take a function
 * whose only effect is a prefetch for one without effects, and drop its calls). */
static inline __attribute__((always_inline)) void prefetch_lines(const scene *s, size_t e,
                                                                 const rsl_contact_state *st) {
    for (int k = 0; k < 2; k++) {
        uint32_t i = s->pairs[2 * e + k];
        __builtin_prefetch(&s->p[i].position.x, 0, 2);
        __builtin_prefetch(&s->p[i].radius, 0, 2);
        __builtin_prefetch(&s->f[i].x, 1, 2);
        __builtin_prefetch(&s->f[i].z, 1, 2);
        __builtin_prefetch(&s->t[i].x, 1, 2);
        __builtin_prefetch(&s->t[i].z, 1, 2);
    }
    __builtin_prefetch(&st->sliding_spring.x, 1, 2);
    __builtin_prefetch(&st->model_memory.x, 1, 2);
    __builtin_prefetch(&st->slip_flags, 1, 2);
}
static inline __attribute__((always_inline)) void prefetch_contact(const scene *s, size_t e) {
    prefetch_lines(s, e, &s->st[e]);
}

/* baseline_NAME: the loop over every contact of NAME_body; baseline_NAME_prefetch: the same with
 * the library's prefetches of the contact AHEAD further on. baseline_NAME_indexed(_prefetch):
 * the same loops with contact c's state at IST[IDX[c]] (the indexed_* rows' layout), as a pair
 * style that keeps one history per neighbour-list entry steps it in place. */
#define BASELINE_LOOPS(NAME)                                                         \
    static void baseline_##NAME(scene *s) {                                          \
        for (size_t c = 0; c < s->nc; c++) NAME##_body(s, c, &s->st[c]);             \
    }                                                                                \
    static void baseline_##NAME##_prefetch(scene *s) {                               \
        size_t nc = s->nc;                                                           \
        for (size_t c = 0; c < nc; c++) {                                            \
            if (c + AHEAD < nc) prefetch_contact(s, c + AHEAD);                      \
            NAME##_body(s, c, &s->st[c]);                                            \
        }                                                                            \
    }                                                                                \
    static void baseline_##NAME##_indexed(scene *s) {                                \
        for (size_t c = 0; c < s->nc; c++) NAME##_body(s, c, &IST[IDX[c]]);          \
    }                                                                                \
    static void baseline_##NAME##_indexed_prefetch(scene *s) {                       \
        size_t nc = s->nc;                                                           \
        for (size_t c = 0; c < nc; c++) {                                            \
            if (c + AHEAD < nc) prefetch_lines(s, c + AHEAD, &IST[IDX[c + AHEAD]]);  \
            NAME##_body(s, c, &IST[IDX[c]]);                                         \
        }                                                                            \
    }

/* The full set's laws on one contact as LAMMPS steps them, from its normal n, sliding and
 * rolling velocities vs and vr, twisting rate wtw, normal force fn and rolling radius rr: the
 * sliding force ft, n x ft and the couple (rolling and twisting moments) on body 1, and the
 * new state (springs, twisting angle, normal, slip flags) written to st. Shared by the pair and
 * wall baselines. */
static inline __attribute__((always_inline)) void full_laws(rsl_contact_state *st,
                                                           const double n[3], const double vs[3],
                                                           const double vr[3], double wtw,
                                                           double fn, double rr, double ft[3],
                                                           double nxft[3], double couple[3]) {
    double xs[3] = {st->sliding_spring.x, st->sliding_spring.y, st->sliding_spring.z};
    double xr[3] = {st->rolling_spring.x, st->rolling_spring.y, st->rolling_spring.z};
    double th = st->twisting_angle;
    double fr[3];
    uint32_t s1, s2, s3;
    lammps_spring(xs, n, vs, KT, GT, MU * fn, ft, &s1);
    lammps_spring(xr, n, vr, KR, GR, MUR * fn, fr, &s2);
    double mt = lammps_twist(&th, wtw, fn, &s3);
    double nxfr[3];
    CROSS(nxft, n, ft);
    CROSS(nxfr, n, fr);
    for (int k = 0; k < 3; k++) couple[k] = rr * nxfr[k] + mt * n[k];
    st->sliding_spring.x = xs[0], st->sliding_spring.y = xs[1], st->sliding_spring.z = xs[2];
    st->rolling_spring.x = xr[0], st->rolling_spring.y = xr[1], st->rolling_spring.z = xr[2];
    st->twisting_angle = th;
    st->previous_normal.x = n[0], st->previous_normal.y = n[1], st->previous_normal.z = n[2];
    st->slip_flags = s1 | s2 << 1 | s3 << 2;
}

/* full: linear history sliding + rolling sds + twisting sds */
static inline __attribute__((always_inline)) void full_body(scene *s, size_t c,
                                                               rsl_contact_state *st) {
    const rsl_sphere *P = s->p;
    uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
    const rsl_sphere *a = &P[i], *b = &P[j];
    double d3[3] = {b->position.x - a->position.x, b->position.y - a->position.y,
                    b->position.z - a->position.z};
    double r = sqrt(DOT(d3, d3)), rinv = 1.0 / r;
    double n[3] = {d3[0] * rinv, d3[1] * rinv, d3[2] * rinv};
    double R1 = a->radius, R2 = b->radius;
    double l1 = (r + R1 - R2) * 0.5, l2 = r - l1;
    double reff = R1 * R2 / (R1 + R2);
    double fn = s->fn[c];
    double w1[3] = {a->angular_velocity.x, a->angular_velocity.y, a->angular_velocity.z};
    double w2[3] = {b->angular_velocity.x, b->angular_velocity.y, b->angular_velocity.z};
    double dv[3] = {b->velocity.x - a->velocity.x, b->velocity.y - a->velocity.y,
                    b->velocity.z - a->velocity.z};
    double dvn = DOT(dv, n);
    /* LAMMPS sliding velocity with full radii: -(dv)_t + (R1 w1 + R2 w2) x n */
    double arm[3] = {R1 * w1[0] + R2 * w2[0], R1 * w1[1] + R2 * w2[1], R1 * w1[2] + R2 * w2[2]};
    double vs[3];
    CROSS(vs, arm, n);
    for (int k = 0; k < 3; k++) vs[k] -= dv[k] - dvn * n[k];
    double dw[3] = {w1[0] - w2[0], w1[1] - w2[1], w1[2] - w2[2]};
    double vr[3];
    CROSS(vr, dw, n);
    for (int k = 0; k < 3; k++) vr[k] *= reff;
    double wtw = DOT(dw, n);

    double ft[3], nxft[3], couple[3];
    full_laws(st, n, vs, vr, wtw, fn, reff, ft, nxft, couple);
    double f1[3] = {ft[0] - fn * n[0], ft[1] - fn * n[1], ft[2] - fn * n[2]};
    s->f[i].x += f1[0], s->f[i].y += f1[1], s->f[i].z += f1[2];
    s->f[j].x -= f1[0], s->f[j].y -= f1[1], s->f[j].z -= f1[2];
    s->t[i].x += l1 * nxft[0] + couple[0];
    s->t[i].y += l1 * nxft[1] + couple[1];
    s->t[i].z += l1 * nxft[2] + couple[2];
    s->t[j].x += l2 * nxft[0] - couple[0];
    s->t[j].y += l2 * nxft[1] - couple[1];
    s->t[j].z += l2 * nxft[2] - couple[2];
}
BASELINE_LOOPS(full)

/* rolltwist: rolling sds + twisting sds, no sliding law (the velocities are not read; the
 * sliding spring is not touched). */
static inline __attribute__((always_inline)) void rolltwist_body(scene *s, size_t c,
                                                               rsl_contact_state *st) {
    const rsl_sphere *P = s->p;
    uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
    const rsl_sphere *a = &P[i], *b = &P[j];
    double d3[3] = {b->position.x - a->position.x, b->position.y - a->position.y,
                    b->position.z - a->position.z};
    double r = sqrt(DOT(d3, d3)), rinv = 1.0 / r;
    double n[3] = {d3[0] * rinv, d3[1] * rinv, d3[2] * rinv};
    double R1 = a->radius, R2 = b->radius;
    double reff = R1 * R2 / (R1 + R2);
    double fn = s->fn[c];
    double dw[3] = {a->angular_velocity.x - b->angular_velocity.x,
                    a->angular_velocity.y - b->angular_velocity.y,
                    a->angular_velocity.z - b->angular_velocity.z};
    double vr[3];
    CROSS(vr, dw, n);
    for (int k = 0; k < 3; k++) vr[k] *= reff;
    double wtw = DOT(dw, n);

    double xr[3] = {st->rolling_spring.x, st->rolling_spring.y, st->rolling_spring.z};
    double th = st->twisting_angle;
    double fr[3];
    uint32_t s2, s3;
    lammps_spring(xr, n, vr, KR, GR, MUR * fn, fr, &s2);
    double mt = lammps_twist(&th, wtw, fn, &s3);
    double nxfr[3];
    CROSS(nxfr, n, fr);
    double couple[3];
    for (int k = 0; k < 3; k++) couple[k] = reff * nxfr[k] + mt * n[k];
    double f1[3] = {-fn * n[0], -fn * n[1], -fn * n[2]};
    s->f[i].x += f1[0], s->f[i].y += f1[1], s->f[i].z += f1[2];
    s->f[j].x -= f1[0], s->f[j].y -= f1[1], s->f[j].z -= f1[2];
    s->t[i].x += couple[0], s->t[i].y += couple[1], s->t[i].z += couple[2];
    s->t[j].x -= couple[0], s->t[j].y -= couple[1], s->t[j].z -= couple[2];
    st->rolling_spring.x = xr[0], st->rolling_spring.y = xr[1], st->rolling_spring.z = xr[2];
    st->twisting_angle = th;
    st->previous_normal.x = n[0], st->previous_normal.y = n[1], st->previous_normal.z = n[2];
    st->slip_flags = s2 << 1 | s3 << 2;
}
BASELINE_LOOPS(rolltwist)

/* sliding: linear history sliding only (the rolling spring and twisting angle not touched). */
static inline __attribute__((always_inline)) void sliding_body(scene *s, size_t c,
                                                               rsl_contact_state *st) {
    const rsl_sphere *P = s->p;
    uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
    const rsl_sphere *a = &P[i], *b = &P[j];
    double d3[3] = {b->position.x - a->position.x, b->position.y - a->position.y,
                    b->position.z - a->position.z};
    double r = sqrt(DOT(d3, d3)), rinv = 1.0 / r;
    double n[3] = {d3[0] * rinv, d3[1] * rinv, d3[2] * rinv};
    double R1 = a->radius, R2 = b->radius;
    double l1 = (r + R1 - R2) * 0.5, l2 = r - l1;
    double fn = s->fn[c];
    double dv[3] = {b->velocity.x - a->velocity.x, b->velocity.y - a->velocity.y,
                    b->velocity.z - a->velocity.z};
    double dvn = DOT(dv, n);
    double arm[3] = {R1 * a->angular_velocity.x + R2 * b->angular_velocity.x,
                     R1 * a->angular_velocity.y + R2 * b->angular_velocity.y,
                     R1 * a->angular_velocity.z + R2 * b->angular_velocity.z};
    double vs[3];
    CROSS(vs, arm, n);
    for (int k = 0; k < 3; k++) vs[k] -= dv[k] - dvn * n[k];

    double xs[3] = {st->sliding_spring.x, st->sliding_spring.y, st->sliding_spring.z};
    double ft[3];
    uint32_t s1;
    lammps_spring(xs, n, vs, KT, GT, MU * fn, ft, &s1);
    double nxft[3];
    CROSS(nxft, n, ft);
    double f1[3] = {ft[0] - fn * n[0], ft[1] - fn * n[1], ft[2] - fn * n[2]};
    s->f[i].x += f1[0], s->f[i].y += f1[1], s->f[i].z += f1[2];
    s->f[j].x -= f1[0], s->f[j].y -= f1[1], s->f[j].z -= f1[2];
    s->t[i].x += l1 * nxft[0], s->t[i].y += l1 * nxft[1], s->t[i].z += l1 * nxft[2];
    s->t[j].x += l2 * nxft[0], s->t[j].y += l2 * nxft[1], s->t[j].z += l2 * nxft[2];
    st->sliding_spring.x = xs[0], st->sliding_spring.y = xs[1], st->sliding_spring.z = xs[2];
    st->previous_normal.x = n[0], st->previous_normal.y = n[1], st->previous_normal.z = n[2];
    st->slip_flags = s1;
}
BASELINE_LOOPS(sliding)

/* ---- memory floor: same bytes, same access pattern, no physics ---- */
static inline __attribute__((always_inline)) void floor_body(scene *s, size_t c,
                                                            rsl_contact_state *st) {
    const rsl_sphere *P = s->p;
    uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
    const double *a = &P[i].position.x, *b = &P[j].position.x;
    double sa = 0, sb = 0;
    for (int k = 0; k < 10; k++) sa += a[k], sb += b[k];
    double x = (sa - sb) * 1e-30 + s->fn[c] * 1e-30;
    double *q = &st->sliding_spring.x;
    for (int k = 0; k < 13; k++) q[k] += x;
    st->slip_flags ^= 1;
    s->f[i].x += x, s->f[i].y += x, s->f[i].z += x;
    s->f[j].x -= x, s->f[j].y -= x, s->f[j].z -= x;
    s->t[i].x += x, s->t[i].y += x, s->t[i].z += x;
    s->t[j].x += x, s->t[j].y += x, s->t[j].z += x;
}

static void floor_plain(scene *s) {
    for (size_t c = 0; c < s->nc; c++) floor_body(s, c, &s->st[c]);
}

/* With the library's prefetches (prefetch_contact). */
static void floor_prefetch(scene *s) {
    size_t nc = s->nc;
    for (size_t c = 0; c < nc; c++) {
        if (c + AHEAD < nc) prefetch_contact(s, c + AHEAD);
        floor_body(s, c, &s->st[c]);
    }
}

/* The same two on the indexed rows' layout (contact c's state at IST[IDX[c]]). */
static void floor_indexed_plain(scene *s) {
    for (size_t c = 0; c < s->nc; c++) floor_body(s, c, &IST[IDX[c]]);
}

static void floor_indexed_prefetch(scene *s) {
    size_t nc = s->nc;
    for (size_t c = 0; c < nc; c++) {
        if (c + AHEAD < nc) prefetch_lines(s, c + AHEAD, &IST[IDX[c + AHEAD]]);
        floor_body(s, c, &IST[IDX[c]]);
    }
}

/* ---- the group wall: one sphere-wall contact per particle, contact c = particle c ---- */

/* Baseline: the full set's physics for a flat wall as the LAMMPS_2021 preset steps it (see
 * the header: midplane torque arm, full-radius sliding rate in the library's order, rolling
 * radius R). The wall normal is unit (the scene's are), so it is used as it is. */
static inline __attribute__((always_inline)) void wall_body(scene *s, size_t c,
                                                           rsl_contact_state *st) {
    const rsl_sphere *a = &s->p[c];
    const rsl_wall *W = &s->walls[c];
    double nw[3] = {W->normal.x, W->normal.y, W->normal.z};
    double n[3] = {-nw[0], -nw[1], -nw[2]};
    double dx[3] = {a->position.x - W->point.x, a->position.y - W->point.y,
                    a->position.z - W->point.z};
    double R = a->radius;
    double overlap = R - DOT(dx, nw);
    double l1 = R - overlap * 0.5;
    double fn = s->fn[c];
    double w1[3] = {a->angular_velocity.x, a->angular_velocity.y, a->angular_velocity.z};
    double wxn[3];
    CROSS(wxn, w1, n);
    /* relative velocity of the contact points (the wall translates), its tangential part, then
     * the arm R - l1 that makes the full radius LAMMPS' */
    double rel[3] = {a->velocity.x + wxn[0] * l1 - W->velocity.x,
                     a->velocity.y + wxn[1] * l1 - W->velocity.y,
                     a->velocity.z + wxn[2] * l1 - W->velocity.z};
    double reln = DOT(rel, n), arm = R - l1;
    double vs[3], vr[3];
    for (int k = 0; k < 3; k++) vs[k] = (rel[k] - n[k] * reln) + wxn[k] * arm;
    for (int k = 0; k < 3; k++) vr[k] = wxn[k] * R;
    double wtw = DOT(w1, n);

    double ft[3], nxft[3], couple[3];
    full_laws(st, n, vs, vr, wtw, fn, R, ft, nxft, couple);
    s->f[c].x += ft[0] - fn * n[0], s->f[c].y += ft[1] - fn * n[1];
    s->f[c].z += ft[2] - fn * n[2];
    s->t[c].x += l1 * nxft[0] + couple[0];
    s->t[c].y += l1 * nxft[1] + couple[1];
    s->t[c].z += l1 * nxft[2] + couple[2];
}

static void baseline_wall(scene *s) {
    for (size_t c = 0; c < s->nc; c++) wall_body(s, c, &s->st[c]);
}

/* The floor of the wall rows: the same bytes as the library's call (the whole wall struct). */
static inline __attribute__((always_inline)) void floor_wall_body(scene *s, size_t c,
                                                                 rsl_contact_state *st) {
    const double *a = &s->p[c].position.x, *w = &s->walls[c].point.x;
    double sa = 0, sw = 0;
    for (int k = 0; k < 10; k++) sa += a[k];
    for (int k = 0; k < 12; k++) sw += w[k];
    double x = (sa - sw) * 1e-30 + s->fn[c] * 1e-30;
    double *q = &st->sliding_spring.x;
    for (int k = 0; k < 13; k++) q[k] += x;
    st->slip_flags ^= 1;
    s->f[c].x += x, s->f[c].y += x, s->f[c].z += x;
    s->t[c].x += x, s->t[c].y += x, s->t[c].z += x;
}

static void floor_wall(scene *s) {
    for (size_t c = 0; c < s->nc; c++) floor_wall_body(s, c, &s->st[c]);
}

/* ---- library calls ---- */

static void percontact(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        rsl_contact_loads out;
        in.normal_force = s->fn[c];
        int32_t status = rsl_contact_step(MODEL, &s->p[i], &s->p[j], &in, &s->st[c], &out);
        if (status != RSL_OK) {
            fprintf(stderr, "rsl_contact_step failed at contact %zu: %s (%s)\n", c,
                    rsl_status_str(status), rsl_last_error_message());
            exit(1);
        }
        s->f[i].x += out.force1.x, s->f[i].y += out.force1.y, s->f[i].z += out.force1.z;
        s->f[j].x -= out.force1.x, s->f[j].y -= out.force1.y, s->f[j].z -= out.force1.z;
        s->t[i].x += out.torque1.x, s->t[i].y += out.torque1.y, s->t[i].z += out.torque1.z;
        s->t[j].x += out.torque2.x, s->t[j].y += out.torque2.y, s->t[j].z += out.torque2.z;
    }
}

/* The host's own particle arrays, from the scene's spheres (untimed). */
static void host_arrays_alloc(scene *s) {
    s->hx = malloc(s->np * 3 * sizeof(double));
    s->hv = malloc(s->np * 3 * sizeof(double));
    s->hw = malloc(s->np * 3 * sizeof(double));
    s->hr = malloc(s->np * sizeof(double));
    if (!s->hx || !s->hv || !s->hw || !s->hr) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    for (size_t k = 0; k < s->np; k++) {
        const rsl_sphere *b = &s->p[k];
        double *x = &s->hx[3 * k], *v = &s->hv[3 * k], *w = &s->hw[3 * k];
        x[0] = b->position.x, x[1] = b->position.y, x[2] = b->position.z;
        v[0] = b->velocity.x, v[1] = b->velocity.y, v[2] = b->velocity.z;
        w[0] = b->angular_velocity.x, w[1] = b->angular_velocity.y, w[2] = b->angular_velocity.z;
        s->hr[k] = b->radius;
    }
}

static void host_arrays_free(scene *s) {
    free(s->hx), free(s->hv), free(s->hw), free(s->hr);
    s->hx = s->hv = s->hw = s->hr = NULL;
}

/* Particle k of the host's arrays as an rsl_sphere, field by field. */
static inline void fill_sphere(const scene *s, size_t k, rsl_sphere *b) {
    const double *x = &s->hx[3 * k], *v = &s->hv[3 * k], *w = &s->hw[3 * k];
    b->position.x = x[0], b->position.y = x[1], b->position.z = x[2];
    b->velocity.x = v[0], b->velocity.y = v[1], b->velocity.z = v[2];
    b->angular_velocity.x = w[0], b->angular_velocity.y = w[1], b->angular_velocity.z = w[2];
    b->radius = s->hr[k];
}

/* Which per-contact entry the percontact rows call: rsl_contact_step_accumulate, or its
 * unchecked form (the *_unchecked_c rows). */
static int UNCHECKED = 0;

static void accumulate_or_die(const scene *s, size_t c, const rsl_sphere *b1,
                              const rsl_sphere *b2, const rsl_contact_input *in) {
    uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
    int32_t status =
        UNCHECKED ? rsl_contact_step_accumulate_unchecked(MODEL, b1, b2, in, &s->st[c], &s->f[i],
                                                          &s->t[i], &s->f[j], &s->t[j])
                  : rsl_contact_step_accumulate(MODEL, b1, b2, in, &s->st[c], &s->f[i],
                                                &s->t[i], &s->f[j], &s->t[j]);
    if (status != RSL_OK) {
        fprintf(stderr, "rsl_contact_step_accumulate failed at contact %zu: %s (%s)\n", c,
                rsl_status_str(status), rsl_last_error_message());
        exit(1);
    }
}

/* percontact_acc with the per-contact k_n (s->kn) in the input, which the models of the other
 * law sets may read (LIGGGHTS' cdt): the rows percontact_acc_c[LAWS]. */
static void percontact_acc_kn(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        in.normal_force = s->fn[c];
        in.normal_stiffness = s->kn[c];
        accumulate_or_die(s, c, &s->p[s->pairs[2 * c]], &s->p[s->pairs[2 * c + 1]], &in);
    }
}

static void percontact_fill(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        rsl_sphere b1, b2;
        fill_sphere(s, s->pairs[2 * c], &b1);
        fill_sphere(s, s->pairs[2 * c + 1], &b2);
        in.normal_force = s->fn[c];
        accumulate_or_die(s, c, &b1, &b2, &in);
    }
}

#define FILL_AHEAD 64
static void percontact_fill64(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    rsl_sphere b[FILL_AHEAD][2];
    for (size_t c0 = 0; c0 < s->nc; c0 += FILL_AHEAD) {
        size_t n = s->nc - c0 < FILL_AHEAD ? s->nc - c0 : FILL_AHEAD;
        for (size_t k = 0; k < n; k++) {
            fill_sphere(s, s->pairs[2 * (c0 + k)], &b[k][0]);
            fill_sphere(s, s->pairs[2 * (c0 + k) + 1], &b[k][1]);
        }
        for (size_t k = 0; k < n; k++) {
            in.normal_force = s->fn[c0 + k];
            accumulate_or_die(s, c0 + k, &b[k][0], &b[k][1], &in);
        }
    }
}

static void percontact_acc(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        in.normal_force = s->fn[c];
        accumulate_or_die(s, c, &s->p[s->pairs[2 * c]], &s->p[s->pairs[2 * c + 1]], &in);
    }
}

/* percontact_acc with the sliding stiffness and damping passed per contact (s->kt, s->gt), as
 * a Hertz-Mindlin host passes its overlap-dependent k_t and gamma_t: the percontact_params
 * rows. */
static void percontact_params(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    in.flags = RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING;
    for (size_t c = 0; c < s->nc; c++) {
        in.normal_force = s->fn[c];
        in.sliding_stiffness = s->kt[c];
        in.sliding_damping = s->gt[c];
        accumulate_or_die(s, c, &s->p[s->pairs[2 * c]], &s->p[s->pairs[2 * c + 1]], &in);
    }
}

/* The group wall's call: rsl_contact_step_wall_accumulate per sphere-wall contact. */
static void percontact_wall(scene *s) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.dt = DT;
    for (size_t c = 0; c < s->nc; c++) {
        in.normal_force = s->fn[c];
        int32_t status =
            UNCHECKED ? rsl_contact_step_wall_accumulate_unchecked(
                            MODEL, &s->p[c], &s->walls[c], &in, &s->st[c], &s->f[c], &s->t[c])
                      : rsl_contact_step_wall_accumulate(MODEL, &s->p[c], &s->walls[c], &in,
                                                         &s->st[c], &s->f[c], &s->t[c]);
        if (status != RSL_OK) {
            fprintf(stderr, "rsl_contact_step_wall_accumulate failed at contact %zu: %s (%s)\n",
                    c, rsl_status_str(status), rsl_last_error_message());
            exit(1);
        }
    }
}

static rsl_batch_options OPTS;
static rsl_batch_report REP; /* report of the last batch call */
/* Per-contact parameters of the materials* rows (MODE MATERIALS: rsl_batch_step_params with
 * PARAMS.material, each contact's index into MODEL's table of coefficient sets). */
static rsl_batch_contact_params PARAMS;
static void batch(scene *s) {
    int32_t status;
    const char *what;
    if (MODE == MATERIALS) {
        what = "rsl_batch_step_params";
        status = rsl_batch_step_params(MODEL, s->p, s->np, s->pairs, s->nc, s->fn, s->kn,
                                       &PARAMS, DT, &OPTS, s->st, s->f, s->t, &REP);
    } else if (MODE == WALLS) {
        /* the group wall: particle spheres[c] against walls[c], states in contact order
         * (state_index NULL), the model's k_t and gamma_t (params NULL: percontact_wall's
         * input sets no flag), kn NULL (percontact_wall's normal_stiffness 0; the full set's
         * laws do not read it) */
        what = "rsl_batch_step_walls";
        status = rsl_batch_step_walls(MODEL, s->p, s->np, s->spheres, s->walls, s->nc, s->fn,
                                      s->kn, NULL, DT, &OPTS, s->st, s->nc, NULL, s->f, s->t,
                                      &REP);
    } else if (MODE == HISTORY) {
        what = "rsl_batch_step_history";
        status = rsl_batch_step_history(MODEL, s->p, s->np, s->pairs, s->nc, s->fn, s->kn, DT,
                                        &OPTS, HIST, s->f, s->t, &REP);
    } else if (MODE == INDEXED) {
        what = "rsl_batch_step_indexed";
        status = rsl_batch_step_indexed(MODEL, s->p, s->np, s->pairs, s->nc, s->fn, s->kn, NULL,
                                        DT, &OPTS, IST, NSTATES, IDX, s->f, s->t, &REP);
    } else if (MODE == DECOMPOSE) {
        what = "rsl_batch_decompose";
        status = rsl_batch_decompose(s->p, s->np, s->pairs, s->nc, NULL, &OPTS, s->dec, &REP);
    } else if (MODE == CONTACT_MAJOR) {
        what = "rsl_batch_step_contacts";
        status = rsl_batch_step_contacts(MODEL, s->b1, s->b2, s->nc, s->fn, s->kn, DT, &OPTS,
                                         s->st, s->loads, &REP);
    } else {
        what = "rsl_batch_step";
        status = rsl_batch_step(MODEL, s->p, s->np, s->pairs, s->nc, s->fn, s->kn, DT, &OPTS,
                                s->st, s->f, s->t, &REP);
    }
    if (status != RSL_OK) {
        fprintf(stderr,
                "%s failed (precision %u, simd %u): %s (%s); processed %llu, failed %llu, "
                "first failed %llu\n",
                what, OPTS.precision, OPTS.simd, rsl_status_str(status),
                rsl_last_error_message(), (unsigned long long)REP.processed,
                (unsigned long long)REP.failed, (unsigned long long)REP.first_failed);
        exit(1);
    }
}

/* Optional filter: only the rows whose name contains it (the floors and baselines always run). */
static const char *ONLY;
/* --set=NAME: run only that physics set. */
static const char *ONLY_SET;
/* --only=SUBSTRING, or --only=NAME$ for the row NAME alone. */
static int want(const char *name) {
    if (!ONLY) return 1;
    size_t n = strlen(ONLY);
    if (n > 0 && ONLY[n - 1] == '$')
        return strlen(name) == n - 1 && strncmp(name, ONLY, n - 1) == 0;
    return strstr(name, ONLY) != NULL;
}

/* Fastest of `reps` timed calls (states and accumulators restored before each, untimed): the
 * least disturbed call on a shared machine. Small batches repeat the call (each repetition
 * restored untimed) to time >= 0.2M contacts per timed call. */
static double timeit(scene *s, void (*fn)(scene *), int reps) {
    double best = INFINITY;
    int inner = s->nc < 100000 ? (int)(200000 / (s->nc ? s->nc : 1)) : 1;
    if (inner < 1) inner = 1;
    for (int r = 0; r < reps; r++) {
        double acc = 0;
        for (int k = 0; k < inner; k++) {
            reset(s);
            double t0 = now();
            fn(s);
            acc += now() - t0;
        }
        if (acc / inner < best) best = acc / inner;
    }
    return best / (double)s->nc * 1e9;
}

/* Contact-major results added to the accumulators (untimed) in contact order, as the
 * particle-major call and the baselines add them. */
static void accumulate_loads(scene *s) {
    for (size_t c = 0; c < s->nc; c++) {
        uint32_t i = s->pairs[2 * c], j = s->pairs[2 * c + 1];
        const rsl_batch_loads *l = &s->loads[c];
        s->f[i].x += l->force1.x, s->f[i].y += l->force1.y, s->f[i].z += l->force1.z;
        s->f[j].x -= l->force1.x, s->f[j].y -= l->force1.y, s->f[j].z -= l->force1.z;
        s->t[i].x += l->torque1.x, s->t[i].y += l->torque1.y, s->t[i].z += l->torque1.z;
        s->t[j].x += l->torque2.x, s->t[j].y += l->torque2.y, s->t[j].z += l->torque2.z;
    }
}

/* The baseline's results of the current physics set. */
static rsl_vec3 *REF_F, *REF_T;
static rsl_contact_state *REF_ST;

/* Which fields MODEL's packed record keeps (a probe state packed and unpacked: a field left
 * out comes back zero). */
static int KEEPS_SLIDING, KEEPS_NORMAL, KEEPS_OFFAXIS;
static void probe_history_layout(void) {
    rsl_contact_state probe, back;
    memset(&probe, 0, sizeof probe);
    probe.sliding_spring.x = probe.previous_normal.x = probe.model_memory.x = 1.0;
    double record[13];
    if (rsl_history_from_state(MODEL, &probe, record) != RSL_OK ||
        rsl_history_to_state(MODEL, record, &back) != RSL_OK)
        exit(1);
    KEEPS_SLIDING = back.sliding_spring.x == 1.0;
    KEEPS_NORMAL = back.previous_normal.x == 1.0;
    KEEPS_OFFAXIS = back.model_memory.x == 1.0;
}

/* The packed histories back into the states for the comparison: the record's fields; the
 * fields a record does not keep (and the slip flags) from the reference. */
static void unpack_history(scene *s) {
    for (size_t c = 0; c < s->nc; c++) {
        rsl_contact_state u;
        if (rsl_history_to_state(MODEL, HIST + c * HWORDS, &u) != RSL_OK) exit(1);
        s->st[c] = REF_ST[c];
        if (KEEPS_SLIDING) s->st[c].sliding_spring = u.sliding_spring;
        s->st[c].rolling_spring = u.rolling_spring;
        s->st[c].twisting_angle = u.twisting_angle;
        if (KEEPS_NORMAL) s->st[c].previous_normal = u.previous_normal;
        if (KEEPS_OFFAXIS) s->st[c].model_memory = u.model_memory;
    }
}

/* Max |difference| of the accumulated forces (torques) from the baseline's, relative to the
 * largest baseline force (torque) component. */
static double loads_diff(const scene *s) {
    double mf = 0, mt = 0, df = 0, dtq = 0;
    for (size_t i = 0; i < s->np; i++) {
        const double *a = &REF_F[i].x, *b = &s->f[i].x, *c = &REF_T[i].x, *d = &s->t[i].x;
        for (int k = 0; k < 3; k++) {
            mf = fmax(mf, fabs(a[k]));
            mt = fmax(mt, fabs(c[k]));
            df = fmax(df, fabs(a[k] - b[k]));
            dtq = fmax(dtq, fabs(c[k] - d[k]));
        }
    }
    return fmax(mf > 0 ? df / mf : df, mt > 0 ? dtq / mt : dtq);
}

/* Max |difference| of the states from the baseline's, per group of fields (sliding spring,
 * rolling spring, twisting angle, off-axis twist, previous normal) relative to the group's
 * largest baseline component; *flags: contacts whose slip flags differ. */
static double state_diff(const scene *s, size_t *flags) {
    static const int lo[5] = {0, 3, 6, 7, 10}, hi[5] = {3, 6, 7, 10, 13};
    double m[5] = {0}, d[5] = {0};
    *flags = 0;
    for (size_t c = 0; c < s->nc; c++) {
        const double *a = &REF_ST[c].sliding_spring.x, *b = &s->st[c].sliding_spring.x;
        for (int g = 0; g < 5; g++)
            for (int k = lo[g]; k < hi[g]; k++) {
                m[g] = fmax(m[g], fabs(a[k]));
                d[g] = fmax(d[g], fabs(a[k] - b[k]));
            }
        *flags += REF_ST[c].slip_flags != s->st[c].slip_flags;
    }
    double r = 0;
    for (int g = 0; g < 5; g++) r = fmax(r, m[g] > 0 ? d[g] / m[g] : d[g]);
    return r;
}

static void row(const char *group, const char *name, double ns, int compare, const scene *s) {
    if (compare) {
        size_t flags;
        double sd = state_diff(s, &flags);
        printf("row %s %s %.3f %.2e %.2e %zu\n", group, name, ns, loads_diff(s), sd, flags);
    } else {
        printf("row %s %s %.3f - - -\n", group, name, ns);
    }
    fflush(stdout);
}

/* The states in contact order in s->st (for the diff): the indexed layout's copied back. */
static void collect_states(scene *s) {
    if (MODE == INDEXED)
        for (size_t c = 0; c < s->nc; c++) s->st[c] = IST[IDX[c]];
}

/* The baseline's results, the reference the rows that follow are compared with. */
static void keep_reference(scene *s) {
    memcpy(REF_F, s->f, s->np * sizeof *REF_F);
    memcpy(REF_T, s->t, s->np * sizeof *REF_T);
    memcpy(REF_ST, s->st, s->nc * sizeof *REF_ST);
}

/* Times a loop without and with prefetches and prints rows NAME_plain<suffix>,
 * NAME_prefetch<suffix> and NAME<suffix> (the faster, the one the ratios use), the results
 * compared with the reference when `compare`; `after_plain` (if any) runs on the first loop's
 * results before its row. */
static void run_pair(scene *s, const char *group, const char *name, const char *suffix,
                     void (*plain)(scene *), void (*prefetch)(scene *), int reps, int compare,
                     void (*after_plain)(scene *)) {
    char label[64];
    double tp = timeit(s, plain, reps);
    collect_states(s);
    if (after_plain) after_plain(s);
    snprintf(label, sizeof label, "%s_plain%s", name, suffix);
    row(group, label, tp, compare, s);
    double tf = timeit(s, prefetch, reps);
    collect_states(s);
    snprintf(label, sizeof label, "%s_prefetch%s", name, suffix);
    row(group, label, tf, compare, s);
    snprintf(label, sizeof label, "%s%s", name, suffix);
    row(group, label, fmin(tp, tf), compare, s);
}

/* Prints the fraction of the reference's contacts at each limit (its slip flags). */
static void print_slips(const scene *s, const char *group, const char *label) {
    size_t slips[3] = {0, 0, 0};
    for (size_t c = 0; c < s->nc; c++)
        for (int b = 0; b < 3; b++) slips[b] += (REF_ST[c].slip_flags >> b) & 1;
    double nc = (double)s->nc;
    printf("info %s, %s: contacts at their limit in the step: sliding %.1f%%, "
           "rolling %.1f%%, twisting %.1f%%\n",
           group, label, 100.0 * (double)slips[0] / nc, 100.0 * (double)slips[1] / nc,
           100.0 * (double)slips[2] / nc);
}

/* Times a set's baseline (run_pair), keeps the results of the loop without prefetches as the
 * reference of the rows that follow (the one with them is compared with it), and prints the
 * fraction of contacts at each limit. */
static void run_baseline(scene *s, const char *group, const char *suffix, void (*plain)(scene *),
                         void (*prefetch)(scene *), int reps) {
    run_pair(s, group, "baseline_c", suffix, plain, prefetch, reps, 1, keep_reference);
    char label[64];
    snprintf(label, sizeof label, "baseline_c%s", suffix);
    print_slips(s, group, label);
}

static void check(int32_t status, const char *what) {
    if (status != RSL_OK) {
        fprintf(stderr, "%s failed: %s (%s)\n", what, rsl_status_str(status),
                rsl_last_error_message());
        exit(1);
    }
}

/* A model of `preset` with linear sliding (KT, GT, MU) or none, EPSD rolling (given KR, GR,
 * MUR) or none, and twisting 0 none, 1 sds (KTW, GTW, MUTW) or 2 marshall (its coefficients
 * derived from the sliding ones). */
static rsl_model *make_model(int32_t preset, int sliding, int rolling, int twisting) {
    rsl_model *m = NULL;
    check(rsl_model_new(preset, &m), "rsl_model_new");
    if (sliding)
        check(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, KT, GT, MU), "rsl_model_set_sliding");
    else
        check(rsl_model_set_sliding(m, RSL_SLIDING_NONE, 0, 0, 0), "rsl_model_set_sliding(NONE)");
    rsl_rolling_params rp;
    check(rsl_model_get_rolling(m, &rp), "rsl_model_get_rolling");
    rp.law = rolling ? RSL_ROLLING_EPSD : RSL_ROLLING_NONE;
    if (rolling) {
        rp.stiffness_rule = RSL_STIFFNESS_GIVEN;
        rp.damping_rule = RSL_DAMPING_GIVEN;
        rp.stiffness = KR;
        rp.damping = GR;
        rp.friction = MUR;
    }
    check(rsl_model_set_rolling(m, &rp), "rsl_model_set_rolling");
    if (twisting)
        check(rsl_model_set_twisting(m, twisting == 2 ? RSL_TWISTING_MARSHALL : RSL_TWISTING_SDS,
                                     KTW, GTW, MUTW),
              "rsl_model_set_twisting");
    else
        check(rsl_model_set_twisting(m, RSL_TWISTING_NONE, 0, 0, 0),
              "rsl_model_set_twisting(NONE)");
    return m;
}

/* A LIGGGHTS_3_8 model with linear sliding (KT, GT, MU); its rolling parameters (the preset's)
 * in *rp, for the caller to change and set. */
static rsl_model *make_liggghts_model(rsl_rolling_params *rp) {
    rsl_model *m = NULL;
    check(rsl_model_new(RSL_PRESET_LIGGGHTS_3_8, &m), "rsl_model_new(LIGGGHTS)");
    check(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, KT, GT, MU), "rsl_model_set_sliding");
    check(rsl_model_get_rolling(m, rp), "rsl_model_get_rolling");
    return m;
}

/* LIGGGHTS' `tangential history rolling_friction cdt`: linear sliding (KT, GT, MU) and the cdt
 * moment eta k_n delta, eta = MUR times the radius (0.5), above a relative spin of 0.5 rad/s. */
static rsl_model *make_cdt_model(void) {
    rsl_rolling_params rp;
    rsl_model *m = make_liggghts_model(&rp);
    rp.law = RSL_ROLLING_CDT;
    rp.friction = MUR * 0.5;
    rp.rate_threshold = 0.5;
    check(rsl_model_set_rolling(m, &rp), "rsl_model_set_rolling(cdt)");
    return m;
}

/* LIGGGHTS' `tangential history rolling_friction epsd2`: linear sliding (KT, GT, MU) and EPSD
 * rolling with the stiffness KT R_eff^2 and the limit MUR R_eff f_n (the length form), no rolling
 * dashpot (LIGGGHTS' epsd2 has none). */
static rsl_model *make_epsd2_model(void) {
    rsl_rolling_params rp;
    rsl_model *m = make_liggghts_model(&rp);
    rp.law = RSL_ROLLING_EPSD;
    rp.form = RSL_FORM_LENGTH;
    rp.stiffness_rule = RSL_STIFFNESS_EPSD2;
    rp.damping_rule = RSL_DAMPING_GIVEN;
    rp.damping = 0.0;
    rp.friction = MUR;
    check(rsl_model_set_rolling(m, &rp), "rsl_model_set_rolling(epsd2)");
    return m;
}

/* ---- mixed materials (the materials<N>_* rows) ---- */

/* Tables of NMAT_TYPES[k] particle types, one coefficient set per unordered pair of types:
 * 1, 3 and 10 sets (LAMMPS' pair_coeff per type pair). */
enum { NMAT = 3, MAXSETS = 10 };
static const unsigned NMAT_TYPES[NMAT] = {1, 2, 4};

/* Scale factors of the nine coefficients (k_t, gamma_t, mu, k_r, gamma_r, mu_r, k_tw, gamma_tw,
 * mu_tw) of each material set: set 0 all 1 (the full set's own model), the others drawn in
 * [0.5, 2) (log-uniform) from a generator of their own, so that the scene's draws are those of
 * the other rows. Set k is the same in every table. */
static double MAT_SCALE[MAXSETS][9];
static uint64_t mat_rng = 987654321;
static double mat_urand(void) {
    mat_rng = mat_rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(mat_rng >> 11) / 9007199254740992.0;
}

/* The full set's model (LAMMPS_2021: linear-history sliding, rolling sds, twisting sds) with
 * its coefficients scaled by f. */
static rsl_model *make_full_scaled(const double f[9]) {
    rsl_model *m = make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 1);
    check(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, KT * f[0], GT * f[1], MU * f[2]),
          "rsl_model_set_sliding(material)");
    rsl_rolling_params rp;
    check(rsl_model_get_rolling(m, &rp), "rsl_model_get_rolling");
    rp.stiffness = KR * f[3];
    rp.damping = GR * f[4];
    rp.friction = MUR * f[5];
    check(rsl_model_set_rolling(m, &rp), "rsl_model_set_rolling(material)");
    check(rsl_model_set_twisting(m, RSL_TWISTING_SDS, KTW * f[6], GTW * f[7], MUTW * f[8]),
          "rsl_model_set_twisting(material)");
    return m;
}

/* A model of the full set (its own coefficients: set 0) with a table of `n` material sets. */
static rsl_model *make_material_model(size_t n) {
    rsl_model *sets[MAXSETS];
    for (size_t k = 0; k < n; k++)
        sets[k] = k == 0 ? make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 1)
                         : make_full_scaled(MAT_SCALE[k]);
    rsl_model *m = make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 1);
    check(rsl_model_set_materials(m, (const rsl_model *const *)sets, n),
          "rsl_model_set_materials");
    size_t count = 0;
    check(rsl_model_material_count(m, &count), "rsl_model_material_count");
    if (count != n) {
        fprintf(stderr, "rsl_model_material_count: %zu sets, expected %zu\n", count, n);
        exit(1);
    }
    for (size_t k = 0; k < n; k++) rsl_model_free(sets[k]);
    return m;
}

/* Each contact's material set for a table of `types` particle types: every particle gets a
 * random type (the types interleaved along the particle ids, as a random mixture), a contact
 * the set of the unordered pair of its particles' types (a <= b: a * types - a (a - 1) / 2 +
 * b - a). *nsets: types (types + 1) / 2; counts[k]: contacts of set k. */
static uint32_t *material_indices(const scene *s, unsigned types, size_t *nsets,
                                  size_t counts[MAXSETS]) {
    unsigned *type = xmalloc(s->np * sizeof *type);
    for (size_t i = 0; i < s->np; i++) {
        type[i] = (unsigned)(mat_urand() * types);
        if (type[i] >= types) type[i] = types - 1;
    }
    uint32_t *mat = xmalloc((s->nc ? s->nc : 1) * sizeof *mat);
    memset(counts, 0, MAXSETS * sizeof *counts);
    for (size_t c = 0; c < s->nc; c++) {
        unsigned a = type[s->pairs[2 * c]], b = type[s->pairs[2 * c + 1]];
        if (a > b) {
            unsigned t = a;
            a = b, b = t;
        }
        mat[c] = a * types - a * (a - 1) / 2 + (b - a);
        counts[mat[c]]++;
    }
    free(type);
    *nsets = (size_t)types * (types + 1) / 2;
    return mat;
}

/* ---- the group wall's scene ---- */

/* The fixed tilted wall normal: a unit vector whose length computes to exactly 1
 * (sqrt((x x + y y) + z z), the library's order), so that the library's normalisation
 * (v / |v|) returns its bits and the baseline may use it as it is. */
static void tilted_unit(double u[3]) {
    double v[3] = {0.3, -0.2, 1.0};
    for (int it = 0; it < 8; it++) {
        double m = sqrt(DOT(v, v));
        if (m == 1.0) {
            for (int k = 0; k < 3; k++) u[k] = v[k];
            return;
        }
        for (int k = 0; k < 3; k++) v[k] /= m;
    }
    fprintf(stderr, "no tilted wall normal of length 1\n");
    exit(1);
}

/* The group wall's scene from workload A's: its particles (shared), one wall per particle
 * (contact c = particle c), f_n, histories and accumulators of its own (see the header). The
 * draws come from the scene generator reseeded for the group (restored after), so the walls
 * do not depend on what ran before and the other rows do not depend on the walls. */
static void build_walls(const scene *s, scene *w) {
    uint64_t saved = rng_state;
    rng_state = 24680;
    size_t n = s->np;
    memset(w, 0, sizeof *w);
    w->np = w->nc = n;
    w->p = s->p;
    w->fn = xmalloc(n * sizeof *w->fn);
    w->walls = xmalloc(n * sizeof *w->walls);
    w->spheres = xmalloc(n * sizeof *w->spheres);
    for (size_t c = 0; c < n; c++) w->spheres[c] = (uint32_t)c;
    w->st0_slip = xcalloc(n, sizeof *w->st0_slip);
    w->st0 = w->st0_slip;
    w->st = xcalloc(n, sizeof *w->st);
    w->f = xcalloc(n, sizeof *w->f);
    w->t = xcalloc(n, sizeof *w->t);
    double tilt[3];
    tilted_unit(tilt);
    static const double up[3] = {0.0, 0.0, 1.0};
    for (size_t c = 0; c < n; c++) {
        const rsl_sphere *q = &s->p[c];
        const double *nw = urand() < 0.5 ? up : tilt;
        double delta = 0.007 + 0.026 * urand();
        double tg[3];
        random_tangent(nw[0], nw[1], nw[2], tg);
        double off = 0.5 * (urand() - 0.5), down = q->radius - delta;
        rsl_wall *W = &w->walls[c];
        W->point.x = q->position.x - down * nw[0] + off * tg[0];
        W->point.y = q->position.y - down * nw[1] + off * tg[1];
        W->point.z = q->position.z - down * nw[2] + off * tg[2];
        W->normal.x = nw[0], W->normal.y = nw[1], W->normal.z = nw[2];
        W->velocity.x = 0.02, W->velocity.y = -0.01, W->velocity.z = 0.005;
        W->angular_velocity.x = W->angular_velocity.y = W->angular_velocity.z = 0.0;
        /* the overlap as the library computes it (R - (x - point) . normal) */
        double dx[3] = {q->position.x - W->point.x, q->position.y - W->point.y,
                        q->position.z - W->point.z};
        double fn = KN * (q->radius - DOT(dx, nw));
        if (!(fn > 0)) {
            fprintf(stderr, "wall contact %zu does not overlap\n", c);
            exit(1);
        }
        w->fn[c] = fn;
        /* previous normal tilted by ~1e-3 from n = -wall normal; springs tangent to it */
        double nx = -nw[0] + 1e-3 * (urand() - 0.5), ny = -nw[1] + 1e-3 * (urand() - 0.5),
               nz = -nw[2] + 1e-3 * (urand() - 0.5);
        double nn = sqrt(nx * nx + ny * ny + nz * nz);
        nx /= nn, ny /= nn, nz /= nn;
        double ts[3], tr[3];
        random_tangent(nx, ny, nz, ts);
        random_tangent(nx, ny, nz, tr);
        double ks = limit_multiple() * MU * fn / KT, kr = limit_multiple() * MUR * fn / KR;
        double mtw = limit_multiple();
        double sign = urand() < 0.5 ? -1.0 : 1.0;
        rsl_contact_state *st = &w->st0_slip[c];
        st->previous_normal.x = nx, st->previous_normal.y = ny, st->previous_normal.z = nz;
        st->sliding_spring.x = ks * ts[0], st->sliding_spring.y = ks * ts[1];
        st->sliding_spring.z = ks * ts[2];
        st->rolling_spring.x = kr * tr[0], st->rolling_spring.y = kr * tr[1];
        st->rolling_spring.z = kr * tr[2];
        st->twisting_angle = sign * mtw * MUTW * fn / KTW;
    }
    rng_state = saved;
}

static void free_walls(scene *w) {
    free(w->fn), free(w->walls), free(w->spheres), free(w->st0_slip), free(w->st), free(w->f);
    free(w->t);
    memset(w, 0, sizeof *w);
}

static const char *LEVEL[4] = {"auto", "scalar", "avx2", "avx512"};
/* --level=NAME: the SIMD level of the rows that otherwise run at the best one. */
static uint32_t BEST_LEVEL = RSL_SIMD_AUTO;

int main(int argc, char **argv) {
    size_t nc = 1200000;
    int reps = 5, npos = 0;
    char workload = 'A';
    for (int a = 1; a < argc; a++) {
        if (strncmp(argv[a], "--workload=", 11) == 0) {
            workload = argv[a][11];
        } else if (strncmp(argv[a], "--slip=", 7) == 0) {
            SLIP = atof(argv[a] + 7);
            if (!(SLIP >= 0 && SLIP <= 1)) {
                fprintf(stderr, "--slip must be in [0, 1]\n");
                return 2;
            }
        } else if (strncmp(argv[a], "--only=", 7) == 0) {
            ONLY = argv[a] + 7;
        } else if (strncmp(argv[a], "--set=", 6) == 0) {
            ONLY_SET = argv[a] + 6;
        } else if (strncmp(argv[a], "--level=", 8) == 0) {
            uint32_t lv = 4;
            for (uint32_t l = 0; l < 4; l++)
                if (strcmp(argv[a] + 8, LEVEL[l]) == 0) lv = l;
            if (lv == 4) {
                fprintf(stderr, "--level must be auto, scalar, avx2 or avx512\n");
                return 2;
            }
            BEST_LEVEL = lv;
        } else if (argv[a][0] == '-') {
            fprintf(stderr, "unknown option %s\n", argv[a]);
            return 2;
        } else if (npos == 0) {
            nc = (size_t)atoll(argv[a]), npos++;
        } else if (npos == 1) {
            reps = atoi(argv[a]), npos++;
        } else {
            ONLY = argv[a]; /* the previous driver's third argument */
        }
    }
    int set_ok = !ONLY_SET || strcmp(ONLY_SET, "full") == 0 || strcmp(ONLY_SET, "rolltwist") == 0 ||
                 strcmp(ONLY_SET, "sliding") == 0 || strcmp(ONLY_SET, "wall") == 0;
    if ((workload != 'A' && workload != 'B') || nc == 0 || reps < 1 || !set_ok) {
        fprintf(stderr,
                "usage: %s [CONTACTS [REPS]] [--workload=A|B] [--slip=F] [--only=SUBSTRING] "
                "[--set=full|rolltwist|sliding|wall]\n",
                argv[0]);
        return 2;
    }
    scene s;
    memset(&s, 0, sizeof s);
    if (workload == 'A')
        build_fcc_sorted(&s, nc);
    else
        build_cubic_permuted(&s, nc);
    finish(&s);
    double gap = 0;
    for (size_t c = 0; c < s.nc; c++)
        gap += fabs((double)s.pairs[2 * c + 1] - (double)s.pairs[2 * c]);
    printf("info workload %c: %s\n", workload,
           workload == 'A' ? "jittered FCC packing, ids in LAMMPS atom-sort order (lexicographic "
                             "bins of 0.55, x fastest), half neighbour list sorted by body 1"
                           : "jittered cubic packing, ids randomly permuted, contacts sorted by "
                             "body 1");
    printf("info contacts %zu particles %zu contacts/particle %.2f mean |id2-id1| %.0f "
           "state_bytes %zu sphere_bytes %zu\n",
           s.nc, s.np, (double)s.nc / (double)s.np, gap / (double)s.nc,
           sizeof(rsl_contact_state), sizeof(rsl_sphere));

    uint32_t simd = rsl_batch_simd_support();
    printf("info library %s simd_support", rsl_version());
    for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++)
        if ((simd >> lv) & 1) printf(" %s", LEVEL[lv]);
    printf("\n");

    enum { FULL, ROLLTWIST, SLIDING, NSETS, NEXTRA = 15 };
    const char *set_name[NSETS] = {"full", "rolltwist", "sliding"};
    const int has_sliding[NSETS] = {1, 0, 1}; /* the sets of the percontact_params rows */
    void (*baseline[NSETS])(scene *) = {baseline_full, baseline_rolltwist, baseline_sliding};
    void (*baseline_prefetch[NSETS])(scene *) = {baseline_full_prefetch, baseline_rolltwist_prefetch,
                                                 baseline_sliding_prefetch};
    void (*baseline_indexed[NSETS])(scene *) = {baseline_full_indexed, baseline_rolltwist_indexed,
                                                baseline_sliding_indexed};
    void (*baseline_indexed_prefetch[NSETS])(scene *) = {baseline_full_indexed_prefetch,
                                                         baseline_rolltwist_indexed_prefetch,
                                                         baseline_sliding_indexed_prefetch};
    rsl_model *set_model[NSETS] = {make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 1),
                                   make_model(RSL_PRESET_LAMMPS_2021, 0, 1, 1),
                                   make_model(RSL_PRESET_LAMMPS_2021, 1, 0, 0)};
    rsl_model *full_exact = make_model(RSL_PRESET_OBJECTIVE, 1, 1, 1),
              *slide_roll_exact = make_model(RSL_PRESET_OBJECTIVE, 1, 1, 0),
              *roll_twist_exact = make_model(RSL_PRESET_OBJECTIVE, 0, 1, 1),
              *sliding_exact = make_model(RSL_PRESET_OBJECTIVE, 1, 0, 0),
              *slide_roll_lammps = make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 0),
              *full_lammps_marshall = make_model(RSL_PRESET_LAMMPS_2021, 1, 1, 2),
              *full_exact_marshall = make_model(RSL_PRESET_OBJECTIVE, 1, 1, 2),
              *roll_exact = make_model(RSL_PRESET_OBJECTIVE, 0, 1, 0),
              *roll_lammps = make_model(RSL_PRESET_LAMMPS_2021, 0, 1, 0),
              *twist_lammps = make_model(RSL_PRESET_LAMMPS_2021, 0, 0, 1),
              *slide_twist_lammps = make_model(RSL_PRESET_LAMMPS_2021, 1, 0, 1),
              *twist_exact = make_model(RSL_PRESET_OBJECTIVE, 0, 0, 1),
              *slide_twist_exact = make_model(RSL_PRESET_OBJECTIVE, 1, 0, 1),
              *slide_cdt_liggghts = make_cdt_model(), *slide_epsd2_liggghts = make_epsd2_model();
    /* other law sets (workload A), each in the group whose floor and baseline it is set
     * against */
    struct {
        const char *name;
        rsl_model *model;
        int group;
    } extra[NEXTRA] = {
        {"full/exact", full_exact, FULL},
        {"slide+roll/exact", slide_roll_exact, FULL},
        {"slide+roll/lammps", slide_roll_lammps, FULL},
        {"full/lammps+marshall", full_lammps_marshall, FULL},
        {"full/exact+marshall", full_exact_marshall, FULL},
        {"slide+twist/lammps", slide_twist_lammps, FULL},
        {"slide+twist/exact", slide_twist_exact, FULL},
        {"slide+cdt/liggghts", slide_cdt_liggghts, FULL},
        {"slide+epsd2/liggghts", slide_epsd2_liggghts, FULL},
        {"roll+twist/exact", roll_twist_exact, ROLLTWIST},
        {"roll/exact", roll_exact, ROLLTWIST},
        {"roll/lammps", roll_lammps, ROLLTWIST},
        {"twist/lammps", twist_lammps, ROLLTWIST},
        {"twist/exact", twist_exact, ROLLTWIST},
        {"sliding/exact", sliding_exact, SLIDING},
    };
    fflush(stdout);

    REF_F = xmalloc(s.np * sizeof *REF_F);
    REF_T = xmalloc(s.np * sizeof *REF_T);
    /* the group wall has one contact per particle */
    REF_ST = xmalloc((s.nc > s.np ? s.nc : s.np) * sizeof *REF_ST);
    HIST = xmalloc(s.nc * 13 * sizeof *HIST);
    char name[160];
    for (int set = 0; set < NSETS; set++) {
        const char *g = set_name[set];
        if (ONLY_SET && strcmp(ONLY_SET, g) != 0) continue;
        run_pair(&s, g, "floor", "", floor_plain, floor_prefetch, reps, 0, NULL);
        s.st0 = s.st0_slip;
        run_baseline(&s, g, "", baseline[set], baseline_prefetch[set], reps);
        MODEL = set_model[set];
        check(rsl_model_history_size(MODEL, &HWORDS), "rsl_model_history_size");
        probe_history_layout();
        if (want("percontact_acc_c"))
            row(g, "percontact_acc_c", timeit(&s, percontact_acc, reps), 1, &s);
        if (has_sliding[set] && want("percontact_params_c"))
            row(g, "percontact_params_c", timeit(&s, percontact_params, reps), 1, &s);
        UNCHECKED = 1;
        if (want("percontact_acc_unchecked_c"))
            row(g, "percontact_acc_unchecked_c", timeit(&s, percontact_acc, reps), 1, &s);
        if (has_sliding[set] && want("percontact_params_unchecked_c"))
            row(g, "percontact_params_unchecked_c", timeit(&s, percontact_params, reps), 1, &s);
        UNCHECKED = 0;
        if (want("percontact_c")) row(g, "percontact_c", timeit(&s, percontact, reps), 1, &s);
        if (want("percontact_fill")) {
            host_arrays_alloc(&s);
            row(g, "percontact_fill_c", timeit(&s, percontact_fill, reps), 1, &s);
            row(g, "percontact_fill64_c", timeit(&s, percontact_fill64, reps), 1, &s);
            host_arrays_free(&s);
        }
        int indexed_baselines = 0; /* the indexed layout's floor and loops measured */
        for (int prec = 0; prec < 2; prec++) {
            const char *p = prec ? "f32" : "f64";
            memset(&OPTS, 0, sizeof OPTS);
            OPTS.precision = prec ? RSL_PRECISION_F32 : RSL_PRECISION_F64;
            MODE = PARTICLE_MAJOR;
            for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
                if (!((simd >> lv) & 1)) continue;
                OPTS.simd = lv;
                snprintf(name, sizeof name, "batch_%s_%s", p, LEVEL[lv]);
                if (!want(name)) continue;
                double t = timeit(&s, batch, reps);
                if (REP.simd != lv) {
                    fprintf(stderr, "%s: asked for SIMD level %u, ran %u\n", name, lv, REP.simd);
                    exit(1);
                }
                row(g, name, t, 1, &s);
            }
            OPTS.simd = BEST_LEVEL;
            snprintf(name, sizeof name, "history_%s", p);
            if (want(name)) {
                MODE = HISTORY;
                double t = timeit(&s, batch, reps);
                unpack_history(&s);
                snprintf(name, sizeof name, "history_%s_%s", p, LEVEL[REP.simd & 3]);
                row(g, name, t, 1, &s);
            }
            snprintf(name, sizeof name, "indexed_%s", p);
            if (want(name)) {
                MODE = INDEXED;
                NSTATES = s.nc + (s.nc + 1) / 2;
                IST = xcalloc(NSTATES, sizeof *IST);
                IDX = xcalloc(s.nc ? s.nc : 1, sizeof *IDX);
                for (size_t c = 0; c < s.nc; c++) IDX[c] = c + c / 2;
                if (!indexed_baselines) {
                    /* The floor and the hand-written loops on the same layout (once per set,
                     * with the first indexed row). */
                    indexed_baselines = 1;
                    run_pair(&s, g, "floor_indexed", "", floor_indexed_plain,
                             floor_indexed_prefetch, reps, 0, NULL);
                    run_pair(&s, g, "baseline_c_indexed", "", baseline_indexed[set],
                             baseline_indexed_prefetch[set], reps, 1, NULL);
                }
                double t = timeit(&s, batch, reps);
                collect_states(&s);
                free(IST);
                free(IDX);
                snprintf(name, sizeof name, "indexed_%s_%s", p, LEVEL[REP.simd & 3]);
                row(g, name, t, 1, &s);
            }
            MODE = CONTACT_MAJOR;
            snprintf(name, sizeof name, "contacts_%s", p);
            if (want(name)) {
                double t = timeit(&s, batch, reps);
                snprintf(name, sizeof name, "contacts_%s_%s", p, LEVEL[REP.simd & 3]);
                accumulate_loads(&s);
                row(g, name, t, 1, &s);
            }
            MODE = PARTICLE_MAJOR;
        }
        /* decomposition: f64 and f32, in group full */
        if (set == FULL) {
            memset(&OPTS, 0, sizeof OPTS);
            OPTS.simd = BEST_LEVEL;
            for (int prec = 0; prec < 2; prec++) {
                OPTS.precision = prec ? RSL_PRECISION_F32 : RSL_PRECISION_F64;
                MODE = DECOMPOSE;
                snprintf(name, sizeof name, "decompose_%s", prec ? "f32" : "f64");
                if (want(name)) {
                    double t = timeit(&s, batch, reps);
                    snprintf(name, sizeof name, "decompose_%s_%s", prec ? "f32" : "f64",
                             LEVEL[REP.simd & 3]);
                    row(g, name, t, 0, &s);
                }
                MODE = PARTICLE_MAJOR;
            }
        }
        /* the other law sets (workload A), before the no-slip rows replace the reference */
        if (workload == 'A') {
            for (int k = 0; k < NEXTRA; k++) {
                if (extra[k].group != set) continue;
                memset(&OPTS, 0, sizeof OPTS);
                OPTS.precision = RSL_PRECISION_F64;
                MODEL = extra[k].model;
                MODE = PARTICLE_MAJOR;
                for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
                    if (!((simd >> lv) & 1)) continue;
                    OPTS.simd = lv;
                    snprintf(name, sizeof name, "batch_f64_%s[%s]", LEVEL[lv], extra[k].name);
                    if (!want(name)) continue;
                    double t = timeit(&s, batch, reps);
                    /* other physics than the baseline's: not compared */
                    row(g, name, t, 0, &s);
                }
                /* the per-contact call on the same model */
                snprintf(name, sizeof name, "percontact_acc_c[%s]", extra[k].name);
                if (want(name))
                    row(g, name, timeit(&s, percontact_acc_kn, reps), 0, &s);
            }
        }
        /* mixed materials (group full, both workloads): the full set's contacts through
         * rsl_batch_step_params with a table of 1, 3 and 10 coefficient sets */
        if (set == FULL && want("materials")) {
            for (size_t k = 1; k < MAXSETS; k++)
                for (int i = 0; i < 9; i++) MAT_SCALE[k][i] = 0.5 * pow(4.0, mat_urand());
            for (int i = 0; i < 9; i++) MAT_SCALE[0][i] = 1.0;
            printf("info materials: scale factors of (k_t gamma_t mu k_r gamma_r mu_r k_tw "
                   "gamma_tw mu_tw) per set:");
            for (size_t k = 0; k < MAXSETS; k++) {
                printf(" set%zu", k);
                for (int i = 0; i < 9; i++) printf("%c%.2f", i ? ',' : ' ', MAT_SCALE[k][i]);
            }
            printf("\n");
            for (int k = 0; k < NMAT; k++) {
                size_t nsets, counts[MAXSETS];
                uint32_t *mat = material_indices(&s, NMAT_TYPES[k], &nsets, counts);
                printf("info materials%zu: %u particle type(s) drawn at random, a contact's set "
                       "the pair of its particles' types; contacts per set:",
                       nsets, NMAT_TYPES[k]);
                for (size_t m = 0; m < nsets; m++)
                    printf(" %.1f%%", 100.0 * (double)counts[m] / (double)s.nc);
                printf("\n");
                MODEL = make_material_model(nsets);
                memset(&PARAMS, 0, sizeof PARAMS);
                PARAMS.material = mat;
                memset(&OPTS, 0, sizeof OPTS);
                OPTS.precision = RSL_PRECISION_F64;
                MODE = MATERIALS;
                for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
                    if (!((simd >> lv) & 1)) continue;
                    OPTS.simd = lv;
                    snprintf(name, sizeof name, "materials%zu_f64_%s", nsets, LEVEL[lv]);
                    if (!want(name)) continue;
                    double t = timeit(&s, batch, reps);
                    if (REP.simd != lv) {
                        fprintf(stderr, "%s: asked for SIMD level %u, ran %u\n", name, lv,
                                REP.simd);
                        exit(1);
                    }
                    /* one set: the baseline's physics (compared); more: other coefficients */
                    row(g, name, t, nsets == 1, &s);
                }
                MODE = PARTICLE_MAJOR;
                memset(&PARAMS, 0, sizeof PARAMS);
                rsl_model_free(MODEL);
                free(mat);
            }
        }
        /* the same set on the no-slip histories: the baseline's best case */
        s.st0 = s.st0_noslip;
        run_baseline(&s, g, "[noslip]", baseline[set], baseline_prefetch[set], reps);
        MODEL = set_model[set];
        if (want("percontact_acc_c"))
            row(g, "percontact_acc_c[noslip]", timeit(&s, percontact_acc, reps), 1, &s);
        if (has_sliding[set] && want("percontact_params_c"))
            row(g, "percontact_params_c[noslip]", timeit(&s, percontact_params, reps), 1, &s);
        for (int prec = 0; prec < 2; prec++) {
            const char *p = prec ? "f32" : "f64";
            memset(&OPTS, 0, sizeof OPTS);
            OPTS.precision = prec ? RSL_PRECISION_F32 : RSL_PRECISION_F64;
            MODE = PARTICLE_MAJOR;
            snprintf(name, sizeof name, "batch_%s", p);
            if (!want(name)) continue;
            double t = timeit(&s, batch, reps);
            snprintf(name, sizeof name, "batch_%s_%s[noslip]", p, LEVEL[REP.simd & 3]);
            row(g, name, t, 1, &s);
        }
        s.st0 = s.st0_slip;
    }
    /* the group wall (workload A): the full set's physics on one sphere-wall contact per
     * particle, against its own floor and baseline */
    if (workload == 'A' && (!ONLY_SET || strcmp(ONLY_SET, "wall") == 0)) {
        const char *g = "wall";
        scene w;
        build_walls(&s, &w);
        MODE = PARTICLE_MAJOR;
        MODEL = set_model[FULL];
        size_t up = 0;
        for (size_t c = 0; c < w.nc; c++) up += w.walls[c].normal.z == 1.0;
        double tilt[3];
        tilted_unit(tilt);
        printf("info wall: %zu sphere-wall contacts (one per particle), wall normal +z for "
               "%.1f%%, (%.6f, %.6f, %.6f) for the others\n",
               w.nc, 100.0 * (double)up / (double)w.nc, tilt[0], tilt[1], tilt[2]);
        row(g, "floor_wall", timeit(&w, floor_wall, reps), 0, &w);
        double t = timeit(&w, baseline_wall, reps);
        keep_reference(&w);
        row(g, "baseline_wall_c", t, 1, &w);
        print_slips(&w, g, "baseline_wall_c");
        if (want("percontact_wall_c"))
            row(g, "percontact_wall_c", timeit(&w, percontact_wall, reps), 1, &w);
        UNCHECKED = 1;
        if (want("percontact_wall_unchecked_c"))
            row(g, "percontact_wall_unchecked_c", timeit(&w, percontact_wall, reps), 1, &w);
        UNCHECKED = 0;
        /* rsl_batch_step_walls over the whole scene in one call, each precision and level */
        MODE = WALLS;
        for (int prec = 0; prec < 2; prec++) {
            const char *p = prec ? "f32" : "f64";
            memset(&OPTS, 0, sizeof OPTS);
            OPTS.precision = prec ? RSL_PRECISION_F32 : RSL_PRECISION_F64;
            for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
                if (!((simd >> lv) & 1)) continue;
                OPTS.simd = lv;
                snprintf(name, sizeof name, "batch_wall_%s_%s_c", p, LEVEL[lv]);
                if (!want(name)) continue;
                double tb = timeit(&w, batch, reps);
                if (REP.simd != lv) {
                    fprintf(stderr, "%s: asked for SIMD level %u, ran %u\n", name, lv, REP.simd);
                    exit(1);
                }
                row(g, name, tb, 1, &w);
            }
        }
        MODE = PARTICLE_MAJOR;
        free_walls(&w);
    }
    return 0;
}
