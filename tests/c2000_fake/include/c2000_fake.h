/* c2000_fake.h - host-only controls of the register fake (tests only). */
#ifndef C2000_FAKE_H
#define C2000_FAKE_H

/* Zero every fake register and the fake CPU state (power-on state for the tests). */
void c2000_fake_reset(void);

#endif /* C2000_FAKE_H */
