/* Batch C API: results equal per-contact calls (every SIMD level the CPU has, both
 * precisions), invalid contacts skipped and reported, call-level errors process nothing. */
#include "rsl_test.h"

#define NP 6
#define NC 5

/* A chain of NP touching particles, contact c between particles c and c + 1, f_n 10 + c. */
static void chain(rsl_sphere p[NP], uint32_t pairs[2 * NC], double fn[NC]) {
    for (int i = 0; i < NP; i++) {
        memset(&p[i], 0, sizeof p[i]);
        p[i].position = rsl_test_vec(0.95 * i, 0.01 * i * i, 0.0);
        p[i].velocity = rsl_test_vec(0.1 * i, -0.05 * i, 0.02);
        p[i].angular_velocity = rsl_test_vec(0.3, -0.2 * i, 0.5 + 0.1 * i);
        p[i].radius = 0.5;
    }
    for (int c = 0; c < NC; c++) {
        pairs[2 * c] = (uint32_t)c;
        pairs[2 * c + 1] = (uint32_t)(c + 1);
        fn[c] = 10.0 + c;
    }
}

/* Adds one contact's loads as the batch calls do: force1 to body i, -force1 to j, torque1 to
 * i, torque2 to j. */
static void add_loads(rsl_vec3 *f, rsl_vec3 *t, uint32_t i, uint32_t j,
                      const rsl_contact_loads *l) {
    f[i].x += l->force1.x, f[i].y += l->force1.y, f[i].z += l->force1.z;
    f[j].x -= l->force1.x, f[j].y -= l->force1.y, f[j].z -= l->force1.z;
    t[i].x += l->torque1.x, t[i].y += l->torque1.y, t[i].z += l->torque1.z;
    t[j].x += l->torque2.x, t[j].y += l->torque2.y, t[j].z += l->torque2.z;
}

/* Per-contact reference of contact c of chain(): rsl_contact_step with its k_t and gamma_t
 * (RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING), as the *_params batch calls pass
 * them; the loads go to *l. */
static int32_t step_with_params(const rsl_model *m, const rsl_sphere *p, const uint32_t *pairs,
                                const double *fn, const double *kt, const double *gt, double dt,
                                int c, rsl_contact_state *state, rsl_contact_loads *l) {
    rsl_contact_input in;
    memset(&in, 0, sizeof in);
    in.normal_force = fn[c];
    in.dt = dt;
    in.flags = RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING;
    in.sliding_stiffness = kt[c];
    in.sliding_damping = gt[c];
    return rsl_contact_step(m, &p[pairs[2 * c]], &p[pairs[2 * c + 1]], &in, state, l);
}

/* Double-precision options of SIMD level lv in *o; 0 when the CPU lacks the level. */
static int level_options(uint32_t lv, rsl_batch_options *o) {
    memset(o, 0, sizeof *o);
    o->simd = lv;
    return (rsl_batch_simd_support() >> lv) & 1;
}

/* EPSD rolling with given coefficients (the preset's form and damping mode kept). */
static void set_rolling_epsd(rsl_model *m) {
    rsl_rolling_params rp;
    CHECK_STATUS(rsl_model_get_rolling(m, &rp), RSL_OK);
    rp.law = RSL_ROLLING_EPSD;
    rp.stiffness = 5e4;
    rp.damping = 1.0;
    rp.friction = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &rp), RSL_OK);
}

static rsl_model *full_model(void) {
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_OBJECTIVE, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 10.0, 0.5), RSL_OK);
    set_rolling_epsd(m);
    CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, 10.0, 0.1, 0.05), RSL_OK);
    return m;
}

void test_batch_matches_per_contact_calls(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    rsl_model *m = full_model();
    const double dt = 1e-4;
    /* Reference: per-contact calls accumulated by hand. */
    rsl_vec3 fr[NP], tr[NP];
    memset(fr, 0, sizeof fr);
    memset(tr, 0, sizeof tr);
    rsl_contact_state sr[NC];
    memset(sr, 0, sizeof sr);
    rsl_contact_loads lr[NC];
    for (int c = 0; c < NC; c++) {
        rsl_contact_input in;
        memset(&in, 0, sizeof in);
        in.normal_force = fn[c];
        in.dt = dt;
        uint32_t i = pairs[2 * c], j = pairs[2 * c + 1];
        CHECK_STATUS(rsl_contact_step(m, &p[i], &p[j], &in, &sr[c], &lr[c]), RSL_OK);
        add_loads(fr, tr, i, j, &lr[c]);
    }
    uint32_t support = rsl_batch_simd_support();
    CHECK((support >> RSL_SIMD_SCALAR) & 1);
    for (uint32_t prec = 0; prec < 2; prec++)
        for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
            rsl_batch_options o;
            memset(&o, 0, sizeof o);
            o.precision = prec;
            o.simd = lv;
            rsl_vec3 f[NP], t[NP];
            memset(f, 0, sizeof f);
            memset(t, 0, sizeof t);
            rsl_contact_state s[NC];
            memset(s, 0, sizeof s);
            rsl_batch_report rep;
            if (!((support >> lv) & 1)) {
                CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, dt, &o, s, f, t, &rep),
                             RSL_ERR_INVALID_ARGUMENT);
                continue;
            }
            CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, dt, &o, s, f, t, &rep),
                         RSL_OK);
            CHECK(rep.processed == NC && rep.failed == 0 && rep.first_failed == RSL_BATCH_NONE);
            CHECK(rep.simd == lv && rep.first_status == RSL_OK);
            /* double: identical (tolerance 0); single: 1e-5 of the load scale (f_n ~ 10). */
            double tol = prec ? 1e-4 : 0.0;
            for (int i = 0; i < NP; i++) {
                CHECK_VEC(f[i], fr[i].x, fr[i].y, fr[i].z, tol);
                CHECK_VEC(t[i], tr[i].x, tr[i].y, tr[i].z, tol);
            }
            for (int c = 0; c < NC; c++) {
                CHECK_VEC(s[c].sliding_spring, sr[c].sliding_spring.x, sr[c].sliding_spring.y,
                          sr[c].sliding_spring.z, prec ? 1e-9 : 0.0);
            }
            /* contact-major */
            rsl_sphere b1[NC], b2[NC];
            for (int c = 0; c < NC; c++) b1[c] = p[pairs[2 * c]], b2[c] = p[pairs[2 * c + 1]];
            rsl_batch_loads out[NC];
            memset(s, 0, sizeof s);
            CHECK_STATUS(rsl_batch_step_contacts(m, b1, b2, NC, fn, NULL, dt, &o, s, out, NULL),
                         RSL_OK);
            for (int c = 0; c < NC; c++) {
                CHECK_VEC(out[c].force1, lr[c].force1.x, lr[c].force1.y, lr[c].force1.z, tol);
                CHECK_VEC(out[c].torque2, lr[c].torque2.x, lr[c].torque2.y, lr[c].torque2.z, tol);
            }
            /* decomposition */
            rsl_decomposition d[NC];
            CHECK_STATUS(rsl_batch_decompose(p, NP, pairs, NC, NULL, &o, d, &rep), RSL_OK);
            for (int c = 0; c < NC; c++) {
                rsl_decomposition e;
                CHECK_STATUS(rsl_decompose(&b1[c], &b2[c], NULL, &e), RSL_OK);
                CHECK_VEC(d[c].rolling_velocity, e.rolling_velocity.x, e.rolling_velocity.y,
                          e.rolling_velocity.z, prec ? 1e-6 : 0.0);
                CHECK(d[c].overlap == e.overlap);
            }
            CHECK_STATUS(rsl_batch_decompose_contacts(b1, b2, NC, NULL, &o, d, NULL), RSL_OK);
        }
    rsl_model_free(m);
}

void test_batch_skips_invalid_contacts(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    pairs[2 * 1 + 1] = 77;   /* contact 1: index out of range */
    fn[3] = NAN;             /* contact 3: non-finite normal force */
    rsl_model *m = full_model();
    rsl_contact_state s[NC];
    memset(s, 0, sizeof s);
    s[1].twisting_angle = 42.0; /* marker: must survive */
    s[3].twisting_angle = 43.0;
    rsl_vec3 f[NP], t[NP];
    memset(f, 0, sizeof f);
    memset(t, 0, sizeof t);
    rsl_batch_report rep;
    CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, s, f, t, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(rep.processed == 3 && rep.failed == 2 && rep.first_failed == 1);
    CHECK(rep.first_status == RSL_ERR_INVALID_ARGUMENT);
    CHECK(s[1].twisting_angle == 42.0 && s[3].twisting_angle == 43.0);
    CHECK(s[0].previous_normal.x != 0.0 && s[4].previous_normal.x != 0.0);
    /* only the NaN force: its own status */
    pairs[2 * 1 + 1] = 2;
    CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, s, f, t, &rep),
                 RSL_ERR_NON_FINITE);
    CHECK(rep.failed == 1 && rep.first_failed == 3);
    /* call-level errors process nothing */
    rsl_contact_state before[NC];
    memcpy(before, s, sizeof s);
    CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, 0.0, NULL, s, f, t, &rep),
                 RSL_ERR_INVALID_TIME_STEP);
    CHECK(rep.processed == 0 && rep.failed == 0);
    CHECK_STATUS(rsl_batch_step(m, p, NP, NULL, NC, fn, NULL, 1e-4, NULL, s, f, t, &rep),
                 RSL_ERR_NULL_POINTER);
    rsl_batch_options o;
    memset(&o, 0, sizeof o);
    o.simd = 9;
    CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, 1e-4, &o, s, f, t, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(memcmp(before, s, sizeof s) == 0);
    /* empty batch: OK, NULL arrays allowed */
    CHECK_STATUS(rsl_batch_step(m, NULL, 0, NULL, 0, NULL, NULL, 1e-4, NULL, NULL, NULL, NULL,
                                &rep),
                 RSL_OK);
    CHECK(rep.processed == 0);
    rsl_model_free(m);
}

/* Packed histories: record sizes per preset, with and without a sliding law (without one the
 * sliding spring is left out: 3 words fewer), pack/unpack, and rsl_batch_step_history equal to
 * rsl_batch_step bit for bit (LAMMPS: 7 words, 4 without sliding; objective: 10), bad records
 * skipped with the same report, call-level errors. */
void test_batch_packed_histories(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    size_t words = 0;
    const int32_t presets[4] = {RSL_PRESET_OBJECTIVE, RSL_PRESET_LAMMPS_2021,
                                RSL_PRESET_LIGGGHTS_3_8, RSL_PRESET_YADE_2023};
    const size_t expected[4] = {10, 7, 7, 13};
    for (int k = 0; k < 8; k++) {
        rsl_model *m = NULL;
        CHECK_STATUS(rsl_model_new(presets[k / 2], &m), RSL_OK);
        /* a new model has no sliding law; odd k sets one */
        const int sliding = k % 2;
        if (sliding)
            CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 10.0, 0.5), RSL_OK);
        CHECK_STATUS(rsl_model_history_size(m, &words), RSL_OK);
        CHECK(words == expected[k / 2] - (sliding ? 0 : 3));
        /* pack then unpack: the record's fields come back, the others are zero */
        rsl_contact_state s, back;
        memset(&s, 0, sizeof s);
        s.sliding_spring = rsl_test_vec(1, 2, 3);
        s.rolling_spring = rsl_test_vec(4, 5, 6);
        s.twisting_angle = 7;
        s.model_memory = rsl_test_vec(8, 9, 10);
        s.previous_normal = rsl_test_vec(11, 12, 13);
        s.slip_flags = 5;
        double h[13];
        CHECK_STATUS(rsl_history_from_state(m, &s, h), RSL_OK);
        /* the record is the run of (sliding 3, rolling 3, twisting 1, normal 3, off-axis 3)
         * from its first word: 0 with a sliding law, 3 without */
        const double *r = h - (sliding ? 0 : 3);
        if (sliding) CHECK(r[0] == 1 && r[2] == 3);
        CHECK(r[3] == 4 && r[5] == 6 && r[6] == 7);
        const size_t end = words + (sliding ? 0 : 3);
        if (end >= 10) CHECK(r[7] == 11 && r[9] == 13);
        if (end == 13) CHECK(r[10] == 8 && r[12] == 10);
        CHECK_STATUS(rsl_history_to_state(m, h, &back), RSL_OK);
        CHECK(back.rolling_spring.z == 6 && back.twisting_angle == 7 && back.slip_flags == 0);
        CHECK(back.sliding_spring.y == (sliding ? 2 : 0));
        CHECK(back.previous_normal.x == (end >= 10 ? 11 : 0));
        CHECK(back.model_memory.y == (end == 13 ? 9 : 0));
        CHECK_STATUS(rsl_history_from_state(m, NULL, h), RSL_ERR_NULL_POINTER);
        CHECK_STATUS(rsl_history_to_state(m, h, NULL), RSL_ERR_NULL_POINTER);
        rsl_model_free(m);
    }
    CHECK_STATUS(rsl_model_history_size(NULL, &words), RSL_ERR_NULL_POINTER);

    for (int k = 0; k < 3; k++) {
        rsl_model *m = k == 0 ? full_model() : NULL;
        if (k >= 1) {
            /* LAMMPS with sliding and twisting (7 words), then rolling and twisting (4) */
            CHECK_STATUS(rsl_model_new(RSL_PRESET_LAMMPS_2021, &m), RSL_OK);
            if (k == 1)
                CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 10.0, 0.5),
                             RSL_OK);
            else
                set_rolling_epsd(m);
            CHECK_STATUS(rsl_model_set_twisting(m, RSL_TWISTING_SDS, 10.0, 0.1, 0.05), RSL_OK);
        }
        CHECK_STATUS(rsl_model_history_size(m, &words), RSL_OK);
        CHECK(words == (k == 0 ? 10u : k == 1 ? 7u : 4u));
        /* two steps of both calls from the same (zero) histories */
        rsl_contact_state s[NC];
        memset(s, 0, sizeof s);
        double h[NC * 13];
        memset(h, 0, sizeof h);
        rsl_vec3 f1[NP], t1[NP], f2[NP], t2[NP];
        memset(f1, 0, sizeof f1);
        memset(t1, 0, sizeof t1);
        memset(f2, 0, sizeof f2);
        memset(t2, 0, sizeof t2);
        rsl_batch_report r1, r2;
        for (int step = 0; step < 2; step++) {
            CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, s, f1, t1, &r1),
                         RSL_OK);
            CHECK_STATUS(rsl_batch_step_history(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, h, f2,
                                                t2, &r2),
                         RSL_OK);
        }
        CHECK(r1.processed == NC && r2.processed == NC && r1.failed == 0 && r2.failed == 0);
        CHECK(r1.simd == r2.simd);
        CHECK(memcmp(f1, f2, sizeof f1) == 0 && memcmp(t1, t2, sizeof t1) == 0);
        /* both equal per-contact rsl_contact_step, the loads added in contact order */
        rsl_contact_state sr[NC];
        memset(sr, 0, sizeof sr);
        rsl_vec3 fr[NP], tr[NP];
        memset(fr, 0, sizeof fr);
        memset(tr, 0, sizeof tr);
        for (int step = 0; step < 2; step++)
            for (int c = 0; c < NC; c++) {
                rsl_contact_input in;
                memset(&in, 0, sizeof in);
                in.normal_force = fn[c];
                in.dt = 1e-4;
                const uint32_t i = pairs[2 * c], j = pairs[2 * c + 1];
                rsl_contact_loads l;
                CHECK_STATUS(rsl_contact_step(m, &p[i], &p[j], &in, &sr[c], &l), RSL_OK);
                add_loads(fr, tr, i, j, &l);
            }
        CHECK(memcmp(f1, fr, sizeof f1) == 0 && memcmp(t1, tr, sizeof t1) == 0);
        CHECK(memcmp(s, sr, sizeof s) == 0);
        for (int c = 0; c < NC; c++) {
            double packed[13];
            CHECK_STATUS(rsl_history_from_state(m, &s[c], packed), RSL_OK);
            CHECK(memcmp(packed, h + c * words, words * sizeof(double)) == 0);
        }
        /* a non-finite record word (the rolling spring's y: word 4, or 1 without the sliding
         * spring): that contact skipped, its record untouched */
        h[2 * words + (k == 2 ? 1 : 4)] = NAN;
        double before[NC * 13];
        memcpy(before, h, sizeof h);
        CHECK_STATUS(rsl_batch_step_history(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, h, f2, t2,
                                            &r2),
                     RSL_ERR_NON_FINITE);
        CHECK(r2.processed == NC - 1 && r2.failed == 1 && r2.first_failed == 2);
        CHECK(memcmp(h + 2 * words, before + 2 * words, words * sizeof(double)) == 0);
        /* call-level errors process nothing */
        memcpy(before, h, sizeof h);
        CHECK_STATUS(rsl_batch_step_history(m, p, NP, pairs, NC, fn, NULL, 1e-4, NULL, NULL, f2,
                                            t2, &r2),
                     RSL_ERR_NULL_POINTER);
        CHECK(r2.processed == 0);
        CHECK_STATUS(rsl_batch_step_history(m, p, NP, pairs, NC, fn, NULL, -1.0, NULL, h, f2, t2,
                                            &r2),
                     RSL_ERR_INVALID_TIME_STEP);
        CHECK(memcmp(before, h, sizeof h) == 0);
        rsl_model_free(m);
    }
}

/* LIGGGHTS' `tangential history rolling_friction cdt` law set (linear sliding, the cdt rolling
 * law on k_n delta, no twisting law): every batch call (state structs and packed histories, every
 * SIMD level, double) equals per-contact rsl_contact_step bit for bit; the cdt moment is at most
 * eta k_n delta; without the per-contact k_n the call is refused and writes nothing. */
void test_batch_liggghts_cdt(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC], kn[NC];
    chain(p, pairs, fn);
    for (int c = 0; c < NC; c++) kn[c] = 1e6 + 1e4 * c;
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_LIGGGHTS_3_8, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 10.0, 0.5), RSL_OK);
    rsl_rolling_params rp;
    CHECK_STATUS(rsl_model_get_rolling(m, &rp), RSL_OK);
    rp.law = RSL_ROLLING_CDT;
    rp.friction = 0.05; /* eta (angle form): a length */
    rp.rate_threshold = 0.1;
    CHECK_STATUS(rsl_model_set_rolling(m, &rp), RSL_OK);
    const double dt = 1e-4;
    /* Reference: two per-contact steps from zero histories, the second's loads summed. */
    rsl_vec3 fr[NP], tr[NP];
    memset(fr, 0, sizeof fr);
    memset(tr, 0, sizeof tr);
    rsl_contact_state sr[NC];
    memset(sr, 0, sizeof sr);
    int turning = 0;
    for (int step = 0; step < 2; step++)
        for (int c = 0; c < NC; c++) {
            rsl_contact_input in;
            memset(&in, 0, sizeof in);
            in.normal_force = fn[c];
            in.normal_stiffness = kn[c];
            in.dt = dt;
            uint32_t i = pairs[2 * c], j = pairs[2 * c + 1];
            rsl_contact_loads l;
            CHECK_STATUS(rsl_contact_step(m, &p[i], &p[j], &in, &sr[c], &l), RSL_OK);
            rsl_vec3 d = {p[j].position.x - p[i].position.x, p[j].position.y - p[i].position.y,
                          p[j].position.z - p[i].position.z};
            double delta = 1.0 - sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            double mr = sqrt(l.rolling_moment.x * l.rolling_moment.x +
                             l.rolling_moment.y * l.rolling_moment.y +
                             l.rolling_moment.z * l.rolling_moment.z);
            CHECK(mr <= 0.05 * kn[c] * delta * (1 + 1e-12));
            turning += mr > 0;
            if (step == 0) continue;
            add_loads(fr, tr, i, j, &l);
        }
    CHECK(turning > 0);
    for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
        rsl_batch_options o;
        if (!level_options(lv, &o)) continue;
        rsl_vec3 f[NP], t[NP], fh[NP], th[NP];
        rsl_contact_state s[NC];
        double h[NC * 7];
        memset(s, 0, sizeof s);
        memset(h, 0, sizeof h);
        size_t words = 0;
        CHECK_STATUS(rsl_model_history_size(m, &words), RSL_OK);
        CHECK(words == 7);
        rsl_batch_report rep, reph;
        for (int step = 0; step < 2; step++) {
            memset(f, 0, sizeof f);
            memset(t, 0, sizeof t);
            memset(fh, 0, sizeof fh);
            memset(th, 0, sizeof th);
            CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, kn, dt, &o, s, f, t, &rep),
                         RSL_OK);
            CHECK_STATUS(rsl_batch_step_history(m, p, NP, pairs, NC, fn, kn, dt, &o, h, fh, th,
                                                &reph),
                         RSL_OK);
        }
        CHECK(rep.processed == NC && rep.failed == 0 && rep.simd == lv);
        CHECK(reph.processed == NC && reph.failed == 0 && reph.simd == lv);
        for (int i = 0; i < NP; i++) {
            CHECK_VEC(f[i], fr[i].x, fr[i].y, fr[i].z, 0.0);
            CHECK_VEC(t[i], tr[i].x, tr[i].y, tr[i].z, 0.0);
        }
        CHECK(memcmp(f, fh, sizeof f) == 0 && memcmp(t, th, sizeof t) == 0);
        for (int c = 0; c < NC; c++)
            CHECK_VEC(s[c].sliding_spring, sr[c].sliding_spring.x, sr[c].sliding_spring.y,
                      sr[c].sliding_spring.z, 0.0);
        /* no k_n: refused, nothing written */
        rsl_contact_state before[NC];
        memcpy(before, s, sizeof s);
        rsl_vec3 f0[NP];
        memcpy(f0, f, sizeof f);
        CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, dt, &o, s, f, t, &rep),
                     RSL_ERR_NULL_POINTER);
        CHECK(rep.processed == 0);
        CHECK(memcmp(before, s, sizeof s) == 0 && memcmp(f0, f, sizeof f) == 0);
    }
    rsl_model_free(m);
}

/* LIGGGHTS' `tangential history rolling_friction epsd2` law set (linear sliding, EPSD rolling
 * with the stiffness rule RSL_STIFFNESS_EPSD2, no twisting law), here in the length form (the
 * limit mu_r R_eff f_n from one mu_r) with LIGGGHTS' per-contact k_t and gamma_t through
 * rsl_batch_step_params: at every SIMD level (double) the loads and states equal per-contact
 * rsl_contact_step with RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING bit for bit; the
 * rolling moment stays within its limit, reached by some contacts and not others; the rolling
 * stiffness k_t R^2 follows each contact's k_t (without params, the model's k_t gives other
 * rolling springs). */
void test_batch_liggghts_epsd2(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC], kt[NC], gt[NC];
    chain(p, pairs, fn);
    for (int c = 0; c < NC; c++) {
        kt[c] = 2e4 * (c + 1);
        gt[c] = 0.5 * c;
    }
    const rsl_batch_contact_params params = {kt, gt, NULL, NULL};
    rsl_model *m = NULL;
    CHECK_STATUS(rsl_model_new(RSL_PRESET_LIGGGHTS_3_8, &m), RSL_OK);
    CHECK_STATUS(rsl_model_set_sliding(m, RSL_SLIDING_LINEAR, 1e5, 10.0, 0.5), RSL_OK);
    rsl_rolling_params rp;
    CHECK_STATUS(rsl_model_get_rolling(m, &rp), RSL_OK);
    rp.law = RSL_ROLLING_EPSD;
    rp.form = RSL_FORM_LENGTH;
    rp.stiffness_rule = RSL_STIFFNESS_EPSD2;
    rp.friction = 0.1; /* mu_r */
    CHECK_STATUS(rsl_model_set_rolling(m, &rp), RSL_OK);
    const double dt = 1e-4, r_eff = 0.25;
    enum { STEPS = 4 };
    /* Reference: per-contact steps from zero histories, the last step's loads summed. */
    rsl_vec3 fr[NP], tr[NP];
    rsl_contact_state sr[NC];
    memset(sr, 0, sizeof sr);
    int at_limit = 0;
    for (int step = 0; step < STEPS; step++) {
        memset(fr, 0, sizeof fr);
        memset(tr, 0, sizeof tr);
        for (int c = 0; c < NC; c++) {
            const uint32_t i = pairs[2 * c], j = pairs[2 * c + 1];
            rsl_contact_loads l;
            CHECK_STATUS(step_with_params(m, p, pairs, fn, kt, gt, dt, c, &sr[c], &l), RSL_OK);
            const rsl_vec3 mr = l.rolling_moment;
            const double moment = sqrt(mr.x * mr.x + mr.y * mr.y + mr.z * mr.z);
            CHECK(moment <= 0.1 * r_eff * fn[c] * (1 + 1e-12));
            if (step == STEPS - 1) at_limit += (sr[c].slip_flags & RSL_SLIP_ROLLING) != 0;
            add_loads(fr, tr, i, j, &l);
        }
    }
    CHECK(at_limit > 0 && at_limit < NC);
    for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++) {
        rsl_batch_options o;
        if (!level_options(lv, &o)) continue;
        rsl_vec3 f[NP], t[NP], fp[NP], tp[NP];
        rsl_contact_state s[NC], plain[NC];
        memset(s, 0, sizeof s);
        memset(plain, 0, sizeof plain);
        rsl_batch_report rep;
        for (int step = 0; step < STEPS; step++) {
            memset(f, 0, sizeof f);
            memset(t, 0, sizeof t);
            CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, &params, dt, &o, s,
                                               f, t, &rep),
                         RSL_OK);
            CHECK(rep.processed == NC && rep.failed == 0 && rep.simd == lv);
            CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, NULL, dt, &o, plain,
                                               fp, tp, NULL),
                         RSL_OK);
        }
        CHECK(memcmp(f, fr, sizeof f) == 0 && memcmp(t, tr, sizeof t) == 0);
        for (int c = 0; c < NC; c++) {
            CHECK(memcmp(&s[c].sliding_spring, &sr[c].sliding_spring, sizeof(rsl_vec3)) == 0);
            CHECK(memcmp(&s[c].rolling_spring, &sr[c].rolling_spring, sizeof(rsl_vec3)) == 0);
            CHECK(s[c].slip_flags == sr[c].slip_flags);
            /* the model's k_t (1e5) for every contact: other rolling springs, except where
             * both are at the limit */
            if (!(s[c].slip_flags & RSL_SLIP_ROLLING))
                CHECK(plain[c].rolling_spring.x != s[c].rolling_spring.x);
        }
    }
    rsl_model_free(m);
}

/* rsl_batch_step_contacts_params: per-contact k_t and gamma_t equal to rsl_contact_step with
 * RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING, bit for bit in double; a negative
 * k_t skips its contact with rsl_contact_step's status; NULL params is the plain call. */
void test_batch_contact_params(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    rsl_model *m = full_model();
    const double dt = 1e-4;
    double kt[NC], gt[NC];
    rsl_sphere b1[NC], b2[NC];
    for (int c = 0; c < NC; c++) {
        kt[c] = 2e4 * (c + 1);
        gt[c] = 0.5 * c;
        b1[c] = p[pairs[2 * c]];
        b2[c] = p[pairs[2 * c + 1]];
    }
    rsl_contact_state sr[NC], sb[NC];
    memset(sr, 0, sizeof sr);
    memset(sb, 0, sizeof sb);
    rsl_batch_loads out[NC];
    rsl_batch_contact_params params = {kt, gt, NULL, NULL};
    rsl_contact_loads ref[NC];
    for (int step = 0; step < 3; step++) {
        for (int c = 0; c < NC; c++) {
            /* b1[c], b2[c] are contact c's particles */
            rsl_contact_loads l;
            CHECK_STATUS(step_with_params(m, p, pairs, fn, kt, gt, dt, c, &sr[c], &l), RSL_OK);
            if (step == 2) ref[c] = l;
        }
        CHECK_STATUS(rsl_batch_step_contacts_params(m, b1, b2, NC, fn, NULL, &params, dt, NULL,
                                                    sb, out, NULL),
                     RSL_OK);
    }
    for (int c = 0; c < NC; c++) {
        CHECK(memcmp(&ref[c].force1, &out[c].force1, sizeof(rsl_vec3)) == 0);
        CHECK(memcmp(&ref[c].torque2, &out[c].torque2, sizeof(rsl_vec3)) == 0);
    }
    /* the same histories after three steps */
    for (int c = 0; c < NC; c++) {
        CHECK(memcmp(&sr[c].sliding_spring, &sb[c].sliding_spring, sizeof(rsl_vec3)) == 0);
        CHECK(memcmp(&sr[c].rolling_spring, &sb[c].rolling_spring, sizeof(rsl_vec3)) == 0);
        CHECK(sr[c].sliding_spring.x != 0.0);
    }
    /* the model's coefficients differ: without params the springs differ */
    rsl_contact_state plain[NC];
    memset(plain, 0, sizeof plain);
    for (int step = 0; step < 3; step++)
        CHECK_STATUS(rsl_batch_step_contacts_params(m, b1, b2, NC, fn, NULL, NULL, dt, NULL,
                                                    plain, out, NULL),
                     RSL_OK);
    CHECK(plain[1].sliding_spring.x != sb[1].sliding_spring.x);
    /* a negative k_t: that contact skipped, untouched */
    kt[2] = -1.0;
    rsl_contact_state before[NC];
    memcpy(before, sb, sizeof sb);
    rsl_batch_report rep;
    CHECK_STATUS(rsl_batch_step_contacts_params(m, b1, b2, NC, fn, NULL, &params, dt, NULL, sb,
                                                out, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(rep.failed == 1 && rep.first_failed == 2 && rep.processed == NC - 1);
    CHECK(memcmp(&before[2], &sb[2], sizeof sb[2]) == 0);
    rsl_model_free(m);
}

/* rsl_batch_step_params: per-contact k_t and gamma_t in the particle-major call; the forces and
 * torques equal rsl_contact_step's with RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING
 * added in contact order, bit for bit in double; NULL params is rsl_batch_step; a negative k_t
 * skips its contact (state and loads untouched) with rsl_contact_step's status. */
void test_batch_step_params(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    rsl_model *m = full_model();
    const double dt = 1e-4;
    double kt[NC], gt[NC];
    for (int c = 0; c < NC; c++) {
        kt[c] = 2e4 * (c + 1);
        gt[c] = 0.5 * c;
    }
    rsl_batch_contact_params params = {kt, gt, NULL, NULL};
    rsl_contact_state sr[NC], sb[NC];
    memset(sr, 0, sizeof sr);
    memset(sb, 0, sizeof sb);
    rsl_vec3 fr[NP], tr[NP], fb[NP], tb[NP];
    for (int step = 0; step < 3; step++) {
        memset(fr, 0, sizeof fr);
        memset(tr, 0, sizeof tr);
        memset(fb, 0, sizeof fb);
        memset(tb, 0, sizeof tb);
        for (int c = 0; c < NC; c++) {
            const uint32_t i = pairs[2 * c], j = pairs[2 * c + 1];
            rsl_contact_loads l;
            CHECK_STATUS(step_with_params(m, p, pairs, fn, kt, gt, dt, c, &sr[c], &l), RSL_OK);
            add_loads(fr, tr, i, j, &l);
        }
        CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL, sb,
                                           fb, tb, NULL),
                     RSL_OK);
        CHECK(memcmp(fr, fb, sizeof fr) == 0);
        CHECK(memcmp(tr, tb, sizeof tr) == 0);
    }
    for (int c = 0; c < NC; c++) {
        CHECK(memcmp(&sr[c].sliding_spring, &sb[c].sliding_spring, sizeof(rsl_vec3)) == 0);
        CHECK(memcmp(&sr[c].rolling_spring, &sb[c].rolling_spring, sizeof(rsl_vec3)) == 0);
        CHECK(sr[c].sliding_spring.x != 0.0);
    }
    /* NULL params: exactly rsl_batch_step, whose springs differ (the model's coefficients) */
    rsl_contact_state plain[NC], plain2[NC];
    memset(plain, 0, sizeof plain);
    memset(plain2, 0, sizeof plain2);
    rsl_vec3 f2[NP], t2[NP];
    memset(fb, 0, sizeof fb);
    memset(tb, 0, sizeof tb);
    memset(f2, 0, sizeof f2);
    memset(t2, 0, sizeof t2);
    CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, NULL, dt, NULL, plain, fb,
                                       tb, NULL),
                 RSL_OK);
    CHECK_STATUS(rsl_batch_step(m, p, NP, pairs, NC, fn, NULL, dt, NULL, plain2, f2, t2, NULL),
                 RSL_OK);
    CHECK(memcmp(plain, plain2, sizeof plain) == 0);
    CHECK(memcmp(fb, f2, sizeof fb) == 0 && memcmp(tb, t2, sizeof tb) == 0);
    CHECK(plain[1].sliding_spring.x != sb[1].sliding_spring.x);
    /* a negative k_t: that contact skipped, its state untouched, its bodies get no load from it */
    kt[2] = -1.0;
    rsl_contact_state before[NC];
    memcpy(before, sb, sizeof sb);
    rsl_batch_report rep;
    memset(fb, 0, sizeof fb);
    memset(tb, 0, sizeof tb);
    CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL, sb, fb,
                                       tb, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK(rep.failed == 1 && rep.first_failed == 2 && rep.processed == NC - 1);
    CHECK(rep.first_status == RSL_ERR_INVALID_ARGUMENT);
    CHECK(memcmp(&before[2], &sb[2], sizeof sb[2]) == 0);
    CHECK(memcmp(&before[1], &sb[1], sizeof sb[1]) != 0);
    /* a params array of the wrong alignment is a call-level error: nothing processed */
    memcpy(before, sb, sizeof sb);
    rsl_vec3 f_before[NP];
    memcpy(f_before, fb, sizeof fb);
    rsl_batch_contact_params odd = {(const double *)((const char *)kt + 1), NULL, NULL, NULL};
    CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, &odd, dt, NULL, sb, fb, tb,
                                       &rep),
                 RSL_ERR_MISALIGNED);
    CHECK(rep.processed == 0);
    CHECK(memcmp(before, sb, sizeof sb) == 0);
    CHECK(memcmp(f_before, fb, sizeof fb) == 0);
    rsl_model_free(m);
}

/* rsl_batch_step_indexed: the histories stepped where the host keeps them (one slot per
 * neighbour-list entry here, every other one touching) give the bits of rsl_batch_step_params
 * on a buffer of the touching contacts' states; the slots not indexed are neither read (they
 * hold NaN, which a read would refuse) nor written; bad indices are a call-level error. */
void test_batch_step_indexed(void) {
    rsl_sphere p[NP];
    uint32_t pairs[2 * NC];
    double fn[NC];
    chain(p, pairs, fn);
    rsl_model *m = full_model();
    const double dt = 1e-4;
    double kt[NC];
    for (int c = 0; c < NC; c++) kt[c] = 3e4 * (c + 1);
    rsl_batch_contact_params params = {kt, NULL, NULL, NULL};
    enum { NS = 2 * NC + 1 };
    rsl_contact_state slots[NS], buffer[NC];
    size_t index[NC];
    memset(buffer, 0, sizeof buffer);
    for (int s = 0; s < NS; s++) {
        memset(&slots[s], 0, sizeof slots[s]);
        slots[s].twisting_angle = NAN;
    }
    for (int c = 0; c < NC; c++) {
        index[c] = (size_t)(2 * c + 1);
        slots[index[c]].twisting_angle = 0.0;
    }
    rsl_vec3 fb[NP], tb[NP], fi[NP], ti[NP];
    for (int step = 0; step < 3; step++) {
        memset(fb, 0, sizeof fb);
        memset(tb, 0, sizeof tb);
        memset(fi, 0, sizeof fi);
        memset(ti, 0, sizeof ti);
        CHECK_STATUS(rsl_batch_step_params(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL,
                                           buffer, fb, tb, NULL),
                     RSL_OK);
        rsl_batch_report rep;
        CHECK_STATUS(rsl_batch_step_indexed(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL,
                                            slots, NS, index, fi, ti, &rep),
                     RSL_OK);
        CHECK(rep.processed == NC && rep.failed == 0);
        CHECK(memcmp(fb, fi, sizeof fb) == 0 && memcmp(tb, ti, sizeof tb) == 0);
        for (int c = 0; c < NC; c++)
            CHECK(memcmp(&buffer[c], &slots[index[c]], sizeof buffer[c]) == 0);
    }
    CHECK(buffer[0].sliding_spring.x != 0.0);
    for (int s = 0; s < NS; s += 2) CHECK(isnan(slots[s].twisting_angle));
    /* indices not strictly increasing, past n_states or misaligned: nothing processed or
     * written */
    rsl_contact_state before[NS];
    memcpy(before, slots, sizeof slots);
    rsl_vec3 f_before[NP];
    memcpy(f_before, fi, sizeof fi);
    const size_t repeated[NC] = {1, 3, 3, 7, 9};
    const size_t falling[NC] = {1, 3, 5, 9, 7};
    const size_t beyond[NC] = {1, 3, 5, 7, NS};
    const size_t *misaligned = (const size_t *)((const char *)index + 1);
    const size_t *bad[4] = {repeated, falling, beyond, misaligned};
    for (int b = 0; b < 4; b++) {
        rsl_batch_report rep;
        CHECK_STATUS(rsl_batch_step_indexed(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL,
                                            slots, NS, bad[b], fi, ti, &rep),
                     b < 3 ? RSL_ERR_INVALID_ARGUMENT : RSL_ERR_MISALIGNED);
        CHECK(rep.processed == 0 && rep.failed == 0);
        CHECK(memcmp(before, slots, sizeof slots) == 0);
        CHECK(memcmp(f_before, fi, sizeof fi) == 0);
    }
    /* a NaN in an indexed state: that contact skipped (its state untouched), the rest stepped */
    slots[index[2]].rolling_spring.y = NAN;
    memcpy(before, slots, sizeof slots);
    rsl_batch_report rep;
    CHECK_STATUS(rsl_batch_step_indexed(m, p, NP, pairs, NC, fn, NULL, &params, dt, NULL, slots,
                                        NS, index, fi, ti, &rep),
                 RSL_ERR_NON_FINITE);
    CHECK(rep.failed == 1 && rep.first_failed == 2 && rep.processed == NC - 1);
    CHECK(memcmp(&before[index[2]], &slots[index[2]], sizeof slots[0]) == 0);
    CHECK(memcmp(&before[index[1]], &slots[index[1]], sizeof slots[0]) != 0);
    /* no contacts: NULL arrays are fine */
    CHECK_STATUS(rsl_batch_step_indexed(m, p, NP, NULL, 0, NULL, NULL, NULL, dt, NULL, NULL, 0,
                                        NULL, fi, ti, NULL),
                 RSL_OK);
    rsl_model_free(m);
}

/* Sphere-wall contacts of NW particles: a floor (normal +z, length 2: any non-zero length is
 * normalised), a moving tilted wall, and a turning wall; particle k touches wall k % 3, and
 * particles 1 and 4 the floor too. */
#define NW 6
#define NWC 8
static void wall_scene(rsl_sphere p[NW], uint32_t sph[NWC], rsl_wall w[NWC], double fn[NWC]) {
    for (int k = 0; k < NW; k++) {
        memset(&p[k], 0, sizeof p[k]);
        p[k].position = rsl_test_vec(1.5 * k, 0.2 * k, 0.49);
        p[k].velocity = rsl_test_vec(0.1 * k, -0.05, 0.02 * k);
        p[k].angular_velocity = rsl_test_vec(0.3 - 0.1 * k, 0.2, -0.4);
        p[k].radius = 0.5;
    }
    int c = 0;
    for (int k = 0; k < NW; k++) {
        const int kinds[2] = {k % 3, 0};
        for (int a = 0; a < (k == 1 || k == 4 ? 2 : 1); a++) {
            const int kind = kinds[a];
            rsl_wall *W = &w[c];
            memset(W, 0, sizeof *W);
            const rsl_vec3 x = p[k].position;
            if (kind == 0) { /* the floor z = 0 */
                W->point = rsl_test_vec(x.x + 0.1, x.y - 0.2, 0.0);
                W->normal = rsl_test_vec(0.0, 0.0, 2.0);
            } else { /* a wall through the point 0.48 from the centre along -u */
                const double u[3] = {kind == 1 ? 0.6 : 0.0, kind == 1 ? 0.0 : -0.6, 0.8};
                W->point = rsl_test_vec(x.x - 0.48 * u[0], x.y - 0.48 * u[1], x.z - 0.48 * u[2]);
                W->normal = rsl_test_vec(u[0], u[1], u[2]);
                W->velocity = rsl_test_vec(0.05, 0.0, -0.01);
                if (kind == 2) W->angular_velocity = rsl_test_vec(0.0, 0.0, 0.7);
            }
            sph[c] = (uint32_t)k;
            fn[c] = (c == 3) ? -2.0 : 5.0 + c; /* one tensile contact */
            c++;
        }
    }
    CHECK(c == NWC);
}

/* rsl_batch_step_walls: bit for bit rsl_contact_step_wall_accumulate's loads and states in
 * double at every SIMD level the CPU has (states in contact order and through an index into
 * a larger array, with per-contact k_t and gamma_t); an invalid contact (a zero wall normal)
 * skipped with the per-contact call's status and nothing written for it; call-level errors
 * process nothing. */
void test_batch_step_walls(void) {
    rsl_sphere p[NW];
    uint32_t sph[NWC];
    rsl_wall w[NWC];
    double fn[NWC], kt[NWC], gt[NWC];
    wall_scene(p, sph, w, fn);
    for (int c = 0; c < NWC; c++) kt[c] = 8e4 + 1e3 * c, gt[c] = 5.0 + c;
    rsl_model *m = full_model();
    const double dt = 1e-4;
    for (int bad = -1; bad < 1; bad++) {
        if (bad == 0) w[5].normal = rsl_test_vec(0.0, 0.0, 0.0);
        /* Reference: the per-contact calls, two steps (the second with the first's history). */
        rsl_vec3 fr[NW], tr[NW];
        memset(fr, 0, sizeof fr);
        memset(tr, 0, sizeof tr);
        rsl_contact_state sr[NWC];
        memset(sr, 0, sizeof sr);
        int32_t bad_status = RSL_OK;
        for (int step = 0; step < 2; step++)
            for (int c = 0; c < NWC; c++) {
                rsl_contact_input in;
                memset(&in, 0, sizeof in);
                in.normal_force = fn[c];
                in.dt = dt;
                in.flags = RSL_INPUT_SLIDING_STIFFNESS | RSL_INPUT_SLIDING_DAMPING;
                in.sliding_stiffness = kt[c];
                in.sliding_damping = gt[c];
                const int32_t st = rsl_contact_step_wall_accumulate(m, &p[sph[c]], &w[c], &in,
                                                                    &sr[c], &fr[sph[c]],
                                                                    &tr[sph[c]]);
                if (c == 5 && bad == 0) bad_status = st;
                else CHECK_STATUS(st, RSL_OK);
            }
        if (bad == 0) CHECK(bad_status == RSL_ERR_INVALID_ARGUMENT);
        for (uint32_t lv = RSL_SIMD_SCALAR; lv <= RSL_SIMD_AVX512; lv++)
            for (int indexed = 0; indexed < 2; indexed++) {
                rsl_batch_options o;
                if (!level_options(lv, &o)) continue;
                rsl_vec3 f[NW], t[NW];
                memset(f, 0, sizeof f);
                memset(t, 0, sizeof t);
                /* indexed: contact c's state at slot 2c + 1 of 2 NWC + 1 slots */
                rsl_contact_state slots[2 * NWC + 1];
                memset(slots, 0, sizeof slots);
                size_t index[NWC];
                for (int c = 0; c < NWC; c++) index[c] = indexed ? 2 * (size_t)c + 1 : (size_t)c;
                rsl_batch_contact_params params;
                memset(&params, 0, sizeof params);
                params.sliding_stiffness = kt;
                params.sliding_damping = gt;
                rsl_batch_report rep;
                for (int step = 0; step < 2; step++) {
                    const int32_t st = rsl_batch_step_walls(
                        m, p, NW, sph, w, NWC, fn, NULL, &params, dt, &o, slots,
                        indexed ? 2 * NWC + 1 : NWC, indexed ? index : NULL, f, t, &rep);
                    CHECK_STATUS(st, bad == 0 ? RSL_ERR_INVALID_ARGUMENT : RSL_OK);
                    CHECK(rep.processed == (uint64_t)(bad == 0 ? NWC - 1 : NWC));
                    CHECK(rep.first_failed == (bad == 0 ? 5u : RSL_BATCH_NONE));
                    CHECK(rep.simd == lv);
                }
                CHECK(memcmp(f, fr, sizeof f) == 0);
                CHECK(memcmp(t, tr, sizeof t) == 0);
                for (int c = 0; c < NWC; c++)
                    CHECK(memcmp(&slots[index[c]], &sr[c], sizeof sr[c]) == 0);
                if (indexed)
                    for (int c = 0; c <= NWC; c++) {
                        rsl_contact_state zero;
                        memset(&zero, 0, sizeof zero);
                        CHECK(memcmp(&slots[2 * c], &zero, sizeof zero) == 0);
                    }
            }
    }
    /* Call-level errors: nothing processed, nothing written. */
    rsl_vec3 f[NW], t[NW];
    memset(f, 0, sizeof f);
    memset(t, 0, sizeof t);
    rsl_contact_state s[NWC];
    memset(s, 0, sizeof s);
    rsl_batch_report rep;
    CHECK_STATUS(rsl_batch_step_walls(m, p, NW, sph, NULL, NWC, fn, NULL, NULL, dt, NULL, s, NWC,
                                      NULL, f, t, &rep),
                 RSL_ERR_NULL_POINTER);
    CHECK(rep.processed == 0 && rep.failed == 0);
    CHECK_STATUS(rsl_batch_step_walls(m, p, NW, sph, w, NWC, fn, NULL, NULL, dt, NULL, s,
                                      NWC - 1, NULL, f, t, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    size_t backwards[NWC];
    for (int c = 0; c < NWC; c++) backwards[c] = (size_t)(NWC - 1 - c);
    CHECK_STATUS(rsl_batch_step_walls(m, p, NW, sph, w, NWC, fn, NULL, NULL, dt, NULL, s, NWC,
                                      backwards, f, t, &rep),
                 RSL_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(rsl_batch_step_walls(m, p, NW, sph, w, NWC, fn, NULL, NULL, -dt, NULL, s, NWC,
                                      NULL, f, t, &rep),
                 RSL_ERR_INVALID_TIME_STEP);
    rsl_vec3 zero3[NW];
    memset(zero3, 0, sizeof zero3);
    CHECK(memcmp(f, zero3, sizeof f) == 0 && memcmp(t, zero3, sizeof t) == 0);
    rsl_contact_state zs[NWC];
    memset(zs, 0, sizeof zs);
    CHECK(memcmp(s, zs, sizeof s) == 0);
    rsl_model_free(m);
}
