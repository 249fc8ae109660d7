/*
 * sil_bench.c - `make bench`: simulated seconds per wall-clock second of
 * the SIL (firmware + simulated board, no CSV) for a 1.2 s speed-mode
 * scenario (start to 500 r/min, load steps 4 -> 6 -> 0 N m as in the
 * paper's figures), in both inverter models. Prints, never asserts.
 */
#include <stdio.h>
#include <time.h>

#include "scenario.h"
#include "sil.h"

#define REPEATS 3   /* best of: the figure is the machine's, not its noise */

static const char *const SETS[] = {
    "controller.mode=speed", "reference.speed_rpm=0:0, 0.1:500",
    "load.torque_Nm=0:0, 0.5:4, 0.95:6, 1.05:0", "run.duration_s=1.2",
};

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(void)
{
    static const char *const models[] = { "plant.model=averaged", "plant.model=switching" };
    for (int m = 0; m < 2; m++) {
        static scenario_t sc;
        char err[SCENARIO_ERR_LEN];
        scenario_defaults(&sc);
        for (size_t i = 0; i < sizeof SETS / sizeof SETS[0]; i++) {
            if (scenario_set(&sc, SETS[i], err, sizeof err) != 0) {
                fprintf(stderr, "sil_bench: %s\n", err);
                return 1;
            }
        }
        if (scenario_set(&sc, models[m], err, sizeof err) != 0 || scenario_finish(&sc, err, sizeof err) != 0) {
            fprintf(stderr, "sil_bench: %s\n", err);
            return 1;
        }
        double best = 0.0;
        sil_result_t res;
        for (int r = 0; r < REPEATS; r++) {
            double t0 = now_s();
            sil_run(&sc, NULL, NULL, &res);
            double speed = sc.run.duration_s / (now_s() - t0);
            best = (speed > best) ? speed : best;
        }
        printf("bench sil %-22s %.1f s simulated: %8.0f x real time (best of %d, %u periods)\n",
               models[m] + sizeof "plant.model=" - 1, sc.run.duration_s, best, REPEATS, res.periods);
    }
    return 0;
}
