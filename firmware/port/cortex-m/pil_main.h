/*
 * Entry point of the PIL image (pil_main.c). startup.S calls `main`; the
 * aocs_pil link defines main = aocs_pil_main (firmware/port/cortex-m/
 * CMakeLists.txt), so this port directory holds one `main` (image_main.c)
 * for the static analysis. Returns the exit status that becomes QEMU's.
 * Cortex-M port only.
 */
#ifndef AOCS_PIL_MAIN_H
#define AOCS_PIL_MAIN_H

int aocs_pil_main(void);

#endif /* AOCS_PIL_MAIN_H */
