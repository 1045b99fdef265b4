/* stickslip_sim: batch simulation of the stick-slip actuator to CSV.
 * Runs a named scenario or a sawtooth given by options; see --help. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_actuator.h"

typedef struct {
    const char *name;
    const char *what;
    float rise_fraction; /* 0: the paper's */
    int direction;       /* 0: the paper's */
} scenario_t;

/* The paper's drive (ss_waveform_paper_f32: 500 Hz, 100 V x 44 nm/V = 4.4 um, 20 cycles) and
 * variants of it; fall times of the trend check. */
static const scenario_t SCENARIOS[] = {
    {"paper", "LS paper Fig. 13: 4.4 um, 500 Hz, 100 us fall, forward", 0.0f, 0},
    {"paper-reverse", "as paper, driven backwards", 0.0f, -1},
    {"fall-20us", "as paper with a 20 us fall", 0.99f, 0},
    {"fall-200us", "as paper with a 200 us fall", 0.90f, 0},
};
#define N_SCENARIOS (sizeof SCENARIOS / sizeof SCENARIOS[0])
#define CHUNK_ROWS 4096u
/* Each edge of the sawtooth must span at least this many integration steps: on the 15 us edges
 * of the diagnosis design the per-cycle step moves by 0.1-0.8 % from 1 us to 2 us (7.5 steps)
 * and by 0.5-3 % at 4 us (3.75 steps); 10 steps keeps it near the 1 us figure. */
#define MIN_STEPS_PER_EDGE 10.0

static void usage(FILE *f)
{
    fprintf(f, "usage: stickslip_sim [options]\n"
               "Simulate the stick-slip actuator (Table I parameters) and write CSV.\n\n"
               "  --scenario NAME      named run (default: paper), see the list below\n"
               "  --frequency-hz F     sawtooth frequency\n"
               "  --amplitude-v A      sawtooth amplitude (44 nm/V piezo gain)\n"
               "  --offset-v O         sawtooth offset\n"
               "  --rise-fraction R    share of the period taken by the slow edge, in (0, 1)\n"
               "  --fall-time-s T      set the fast edge duration instead of --rise-fraction\n"
               "  --direction D        +1 (forward) or -1 (backward)\n"
               "  --cycles N           periods played\n"
               "  --hold-s T           time recorded after the last period (drive at offset)\n"
               "  --model ls|lugre|gms friction model (default ls)\n"
               "  --dt-s DT            integration step (default 1e-6)\n"
               "  --decimation N       write every N-th step (default 1)\n"
               "  --out FILE           output CSV (default: standard output)\n"
               "  --help               this text\n\nscenarios:\n");
    for (size_t i = 0; i < N_SCENARIOS; ++i) {
        fprintf(f, "  %-14s %s\n", SCENARIOS[i].name, SCENARIOS[i].what);
    }
}

static int fail(const char *msg, const char *opt, const char *arg)
{
    fprintf(stderr, "stickslip_sim: %s: %s '%s'\n(see --help)\n", opt, msg, arg);
    return 2;
}

static int parse_double(const char *opt, const char *arg, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(arg, &end);
    if (end == arg || *end != '\0' || errno != 0 || !isfinite(v)) {
        return fail("expected a finite number, got", opt, arg);
    }
    *out = v;
    return 0;
}

static int parse_long(const char *opt, const char *arg, long lo, long hi, long *out)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(arg, &end, 10);
    if (end == arg || *end != '\0' || errno != 0) {
        return fail("expected an integer, got", opt, arg);
    }
    if (v < lo || v > hi) {
        return fail("integer out of range, got", opt, arg);
    }
    *out = v;
    return 0;
}

int main(int argc, char **argv)
{
    enum {
        O_SCEN = 1,
        O_F,
        O_A,
        O_OFF,
        O_R,
        O_FALL,
        O_DIR,
        O_CYC,
        O_HOLD,
        O_MODEL,
        O_DT,
        O_DEC,
        O_OUT,
        O_HELP
    };
    static const struct option opts[] = {{"scenario", required_argument, NULL, O_SCEN},
                                         {"frequency-hz", required_argument, NULL, O_F},
                                         {"amplitude-v", required_argument, NULL, O_A},
                                         {"offset-v", required_argument, NULL, O_OFF},
                                         {"rise-fraction", required_argument, NULL, O_R},
                                         {"fall-time-s", required_argument, NULL, O_FALL},
                                         {"direction", required_argument, NULL, O_DIR},
                                         {"cycles", required_argument, NULL, O_CYC},
                                         {"hold-s", required_argument, NULL, O_HOLD},
                                         {"model", required_argument, NULL, O_MODEL},
                                         {"dt-s", required_argument, NULL, O_DT},
                                         {"decimation", required_argument, NULL, O_DEC},
                                         {"out", required_argument, NULL, O_OUT},
                                         {"help", no_argument, NULL, O_HELP},
                                         {NULL, 0, NULL, 0}};

    const scenario_t *sc = &SCENARIOS[0];
    /* NAN / 0: not given (the scenario's or the paper's value is used) */
    double f = NAN, a = NAN, off = 0, r = NAN, fall = NAN, hold = 0, dt = 1e-6;
    long dir = 0, cycles = -1, dec = 1;
    const char *model = "ls";
    const char *out_path = NULL;
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        int e = 0;
        switch (c) {
        case O_SCEN: {
            sc = NULL;
            for (size_t i = 0; i < N_SCENARIOS; ++i) {
                if (strcmp(optarg, SCENARIOS[i].name) == 0) {
                    sc = &SCENARIOS[i];
                }
            }
            if (sc == NULL) {
                return fail("unknown scenario", "--scenario", optarg);
            }
            break;
        }
        case O_F: e = parse_double("--frequency-hz", optarg, &f); break;
        case O_A: e = parse_double("--amplitude-v", optarg, &a); break;
        case O_OFF: e = parse_double("--offset-v", optarg, &off); break;
        case O_R: e = parse_double("--rise-fraction", optarg, &r); break;
        case O_FALL: e = parse_double("--fall-time-s", optarg, &fall); break;
        case O_DIR:
            e = parse_long("--direction", optarg, -1, 1, &dir);
            if (e == 0 && dir == 0) {
                return fail("expected +1 (forward) or -1 (backward), got", "--direction", optarg);
            }
            break;
        case O_CYC: e = parse_long("--cycles", optarg, 0, 1000000, &cycles); break;
        case O_HOLD: e = parse_double("--hold-s", optarg, &hold); break;
        case O_MODEL:
            if (strcmp(optarg, "ls") != 0 && strcmp(optarg, "lugre") != 0 && strcmp(optarg, "gms") != 0) {
                return fail("expected ls, lugre or gms, got", "--model", optarg);
            }
            model = optarg;
            break;
        case O_DT: e = parse_double("--dt-s", optarg, &dt); break;
        case O_DEC: e = parse_long("--decimation", optarg, 1, 1000000, &dec); break;
        case O_OUT: out_path = optarg; break;
        case O_HELP: usage(stdout); return 0;
        default:
            fprintf(stderr, "stickslip_sim: unknown or incomplete option '%s'\n(see --help)\n",
                    argv[optind - 1]);
            return 2;
        }
        if (e != 0) {
            return e;
        }
    }
    if (optind < argc) {
        return fail("unexpected argument", "command line", argv[optind]);
    }
    /* a given value is honoured exactly or refused: never replaced by a default */
    if (!(dt > 0.0)) {
        fprintf(stderr, "stickslip_sim: --dt-s: the integration step must be > 0 s, got %g\n", dt);
        return 2;
    }
    if (!isnan(f) && !(f > 0.0)) {
        fprintf(stderr, "stickslip_sim: --frequency-hz: must be > 0 Hz, got %g\n", f);
        return 2;
    }
    if (!isnan(r) && !(r > 0.0 && r < 1.0)) {
        fprintf(stderr, "stickslip_sim: --rise-fraction: must be in (0, 1), got %g\n", r);
        return 2;
    }
    if (!isnan(r) && !isnan(fall)) {
        fprintf(stderr, "stickslip_sim: --rise-fraction and --fall-time-s: give one of them, not both\n");
        return 2;
    }
    if (!isnan(fall) && !(fall > 0.0)) {
        fprintf(stderr, "stickslip_sim: --fall-time-s: must be > 0 s, got %g\n", fall);
        return 2;
    }
    if (hold < 0 || hold > 3600) {
        fprintf(stderr, "stickslip_sim: --hold-s: must be in [0, 3600] s, got %g\n", hold);
        return 2;
    }
    const ss_waveform_config_f32_t paper = ss_waveform_paper_f32();
    if (dir == 0) {
        dir = (sc->direction != 0) ? sc->direction : paper.direction;
    }
    if (isnan(f)) {
        f = (double)paper.frequency_hz;
    }
    if (isnan(a)) {
        a = (double)paper.amplitude_v;
    }
    if (cycles < 0) {
        cycles = (long)paper.cycles;
    }
    if (!isnan(fall)) {
        if (fall * f >= 1.0) {
            fprintf(stderr,
                    "stickslip_sim: --fall-time-s: %g s does not fit in the %g s period of "
                    "%g Hz\n",
                    fall, 1.0 / f, f);
            return 2;
        }
        r = 1.0 - fall * f;
    } else if (isnan(r)) {
        r = (double)((sc->rise_fraction > 0.0f) ? sc->rise_fraction : paper.rise_fraction);
    }
    const double short_edge_s = fmin(r, 1.0 - r) / f;
    if (short_edge_s < MIN_STEPS_PER_EDGE * dt) {
        fprintf(stderr,
                "stickslip_sim: --dt-s: a %g s step does not resolve the %g s edge of the sawtooth "
                "(%g Hz, rise fraction %g): at least %g steps per edge are needed, so dt <= %g s\n",
                dt, short_edge_s, f, r, MIN_STEPS_PER_EDGE, short_edge_s / MIN_STEPS_PER_EDGE);
        return 2;
    }

    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    cfg.dt_s = (float)dt;
    cfg.friction_model = (strcmp(model, "lugre") == 0) ? SS_FRICTION_LUGRE
                         : (strcmp(model, "gms") == 0) ? SS_FRICTION_GMS
                                                       : SS_FRICTION_LS;
    ss_waveform_config_f32_t wave =
        ss_waveform_sawtooth_f32((float)f, (float)a, (float)off, (float)r, (int32_t)dir, (uint32_t)cycles);
    ss_waveform_state_f32_t wst;
    ss_actuator_state_f32_t st;
    ss_status_t status = ss_waveform_init_f32(&wave, cfg.dt_s, &wst);
    if (status != SS_OK) {
        fprintf(stderr,
                "stickslip_sim: waveform rejected: %s (frequency %g Hz, amplitude %g V, offset %g V, "
                "rise fraction %g, direction %ld)\n",
                ss_status_str(status), f, a, off, r, dir);
        return 2;
    }
    status = ss_actuator_init_f32(&cfg, &st, ss_waveform_value_f32(&wave, &wst));
    if (status != SS_OK) {
        fprintf(stderr, "stickslip_sim: actuator rejected: %s (dt %g s)\n", ss_status_str(status), dt);
        return 2;
    }
    const double total_s = (double)cycles / f + hold;
    const double n_steps_d = floor(total_s / dt + 0.5);
    if (n_steps_d > 4.0e9) {
        fprintf(stderr, "stickslip_sim: run too long: %.0f steps (limit 4e9)\n", n_steps_d);
        return 2;
    }
    FILE *out = stdout;
    if (out_path != NULL && strcmp(out_path, "-") != 0) {
        out = fopen(out_path, "w");
        if (out == NULL) {
            fprintf(stderr, "stickslip_sim: --out: cannot open '%s': %s\n", out_path, strerror(errno));
            return 1;
        }
    }
    const char *states = "level_n,presliding_n";
    if (cfg.friction_model == SS_FRICTION_LUGRE) {
        states = "z_m,zdot_m_per_s";
    } else if (cfg.friction_model == SS_FRICTION_GMS) {
        states = "level_n,elastic_n";
    }
    fprintf(out, "t_s,drive_v,x_p_m,x_rod_m,x_slider_m,friction_n,%s\n", states);

    /* cppcheck-suppress unassignedVariable ; written by the library through the trace struct */
    static uint32_t step[CHUNK_ROWS];
    static float col[8][CHUNK_ROWS];
    ss_actuator_trace_f32_t tr = {step, col[0], col[1], col[2], col[3], NULL,
                                  NULL, col[4], col[5], col[6], NULL,   CHUNK_ROWS};
    ss_actuator_record_f32(&cfg, &st, &tr, 0);
    uint32_t rows = 1;
    uint32_t left = (uint32_t)n_steps_d;
    const double x_start = 0.0;
    double x_end;
    for (;;) {
        for (uint32_t i = 0; i < rows; ++i) {
            fprintf(out, "%.9g,%.7g,%.7g,%.7g,%.9g,%.7g,%.7g,%.7g\n", (double)step[i] * dt, (double)col[0][i],
                    (double)col[1][i], (double)col[2][i], (double)col[3][i], (double)col[4][i],
                    (double)col[5][i], (double)col[6][i]);
        }
        if (left == 0 || status != SS_OK) {
            break;
        }
        uint32_t n = left < CHUNK_ROWS * (uint32_t)dec ? left : CHUNK_ROWS * (uint32_t)dec;
        status = ss_actuator_run_f32(&cfg, &st, &wave, &wst, n, (uint32_t)dec, &tr, &rows);
        left -= n;
    }
    x_end = (double)st.x_slider.hi_m + (double)st.x_slider.lo_m;
    /* a full disk or a closed pipe shows only here: the output was not written */
    int write_failed = (fflush(out) != 0) || ferror(out);
    if (out != stdout && fclose(out) != 0) {
        write_failed = 1;
    }
    if (write_failed) {
        fprintf(stderr, "stickslip_sim: --out: writing '%s' failed: %s\n", out_path != NULL ? out_path : "-",
                strerror(errno));
        return 1;
    }
    if (status != SS_OK) {
        fprintf(stderr, "stickslip_sim: stopped: %s\n", ss_status_str(status));
        return 1;
    }
    if (cycles > 0) {
        fprintf(stderr, "stickslip_sim: %s model, %ld cycles, mean step %.7g m per cycle\n", model, cycles,
                (x_end - x_start) / (double)cycles);
    }
    return 0;
}
