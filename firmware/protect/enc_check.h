/*
 * enc_check.h - the encoder and the motor's wiring checked against a
 * commanded rotation: direction, counts per turn, pole pairs and the
 * order of the phases. Used by build level 3 (app.h: an open-loop
 * rotating voltage vector) and by the commissioning (commission.h: the
 * phase order from a fast vector the rotor does not follow, before any
 * current loop is closed; direction and pole pairs from its current-
 * controlled sweep): any caller that turns a vector by a commanded
 * electrical angle it knows can use it.
 *
 * Use (one check):
 *   enc_check_init(&e, &cfg)            start-up: the controller's counts per
 *                                       turn and pole pairs
 *   enc_check_start(&e, count)          ISR: the rotor already follows the
 *                                       vector (one electrical turn in)
 *   enc_check_step(&e, ...)             ISR, every period of the measurement:
 *                                       the commanded angle's step, its cos and
 *                                       sin, the measured currents and count
 *   enc_check_verdict(&e, &out)         ISR once or background, after whole
 *                                       electrical turns: DONE or the fault
 *   enc_check_phase_order(&e, &out)     the same, the phase order alone (a
 *                                       vector the rotor does not follow)
 *
 * The verdict, in this order (each from the configured values; no motor
 * constant of its own):
 *   PHASE_ORDER        the measured current vector turns against the
 *                      commanded one: its part demodulated at -theta
 *                      (negative sequence) exceeds the part at +theta.
 *                      (Legs swapped before the current sensors. A pair
 *                      swapped after them, between sensors and motor, is
 *                      electrically the same as a reversed encoder and
 *                      shows as ENCODER_DIRECTION: watch the shaft.)
 *   ENCODER_DIRECTION  the count ran against the commanded angle (or not
 *                      at all). Snapshot: the counts, limit 0.
 *   POLE_PAIRS         the pole pairs the counts give, p^ = (commanded
 *                      angle / 2 pi) x counts per turn / |counts|, further
 *                      from the configured p than half an electrical turn
 *                      of lag over the travelled angle allows:
 *                      |p^ - p| > p pi / |angle|. Over one mechanical turn
 *                      that is 0.5: p^ rounds to p. Counts per turn that
 *                      are wrong by more than the same fraction show here
 *                      too, as a p^ that is no whole number. Snapshot: p^,
 *                      limit p.
 */
#ifndef ENC_CHECK_H
#define ENC_CHECK_H

#include <stdint.h>

#include "app_step.h"

typedef struct {
    uint32_t counts_per_turn;   /* the controller's: 4 x encoder lines */
    uint16_t pole_pairs;        /* the controller's */
} enc_check_cfg_t;

typedef struct {
    enc_check_cfg_t cfg;
    uint32_t count_last;        /* the last count seen */
    int32_t counts;             /* signed sum of the count's steps since the start */
    float angle_el_rad;         /* signed sum of the commanded angle's steps [rad el] */
    float i_pos_A[2];           /* sums of i e^(-j theta): the current's positive sequence [A] */
    float i_neg_A[2];           /* sums of i e^(+j theta): its negative sequence [A] */
    uint32_t n;                 /* periods summed */
} enc_check_t;

/* What a check measured (for the report and the snapshot). */
typedef struct {
    int32_t counts;             /* the count's travel [counts] */
    float angle_el_rad;         /* the commanded angle's travel [rad el] */
    float pole_pairs_est;       /* p^ (0 when the count did not move) */
    float i_pos_A;              /* mean positive-sequence current [A] */
    float i_neg_A;              /* mean negative-sequence current [A] */
} enc_check_out_t;

/* Start-up: copy *cfg. */
void enc_check_init(enc_check_t *e, const enc_check_cfg_t *cfg);

/* ISR: the measurement starts at this period's count. */
void enc_check_start(enc_check_t *e, uint32_t enc_count);

/* ISR, every period of the measurement: the commanded angle moved by
 * dangle_el_rad [rad el] to the angle whose cos_el, sin_el are given; the
 * stator currents i_alpha_A, i_beta_A [A] (offsets removed) and the count
 * of this period's sample. */
void enc_check_step(enc_check_t *e, float dangle_el_rad, float cos_el, float sin_el, float i_alpha_A,
                    float i_beta_A, uint32_t enc_count);

/* ISR once or background, after whole electrical turns: DONE when all
 * three checks pass, else the first fault (see above); *out filled. */
app_step_t enc_check_verdict(const enc_check_t *e, enc_check_out_t *out);

/* The same for the first check alone (PHASE_ORDER): for a vector turned
 * faster than the rotor follows, whose count does not move. */
app_step_t enc_check_phase_order(const enc_check_t *e, enc_check_out_t *out);

#endif /* ENC_CHECK_H */
