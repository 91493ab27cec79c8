/* Checks the viewer's scripted screenshots (binary PPM): each shows hair (not blank, not one
 * colour), and the wet frame differs from the dry one where the hair is.
 * usage: image_check DRY.ppm WET.ppm   (exit 0 when both hold) */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int w, h;
    uint8_t *px;
} Image;

static Image load(const char *path) {
    Image im = {0, 0, NULL};
    FILE *f = fopen(path, "rb");
    int maxv = 0;
    if (!f || fscanf(f, "P6 %d %d %d", &im.w, &im.h, &maxv) != 3 || maxv != 255 || fgetc(f) == EOF) {
        fprintf(stderr, "image_check: %s is not a binary PPM\n", path);
        exit(1);
    }
    size_t n = (size_t)im.w * im.h * 3;
    im.px = malloc(n);
    if (!im.px || fread(im.px, 1, n, f) != n) {
        fprintf(stderr, "image_check: %s is truncated\n", path);
        exit(1);
    }
    fclose(f);
    return im;
}

/* Pixels that differ from the top-left (background) pixel by more than a little. */
static int lit(const Image *im, size_t i) {
    int d = 0;
    for (int c = 0; c < 3; c++) d += abs((int)im->px[3 * i + c] - (int)im->px[c]);
    return d > 24;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s DRY.ppm WET.ppm\n", argv[0]);
        return 2;
    }
    Image dry = load(argv[1]), wet = load(argv[2]);
    if (dry.w != wet.w || dry.h != wet.h) return fprintf(stderr, "image_check: sizes differ\n"), 1;
    size_t n = (size_t)dry.w * dry.h, lit_dry = 0, lit_wet = 0, hair = 0, changed = 0;
    for (size_t i = 0; i < n; i++) {
        int a = lit(&dry, i), b = lit(&wet, i);
        lit_dry += a;
        lit_wet += b;
        if (a || b) {
            hair++;
            int d = 0;
            for (int c = 0; c < 3; c++) d += abs((int)dry.px[3 * i + c] - (int)wet.px[3 * i + c]);
            changed += d > 24;
        }
    }
    double f_dry = (double)lit_dry / n, f_wet = (double)lit_wet / n, f_changed = hair ? (double)changed / hair : 0;
    printf("image_check: hair covers %.1f%% (dry) and %.1f%% (wet) of the frame; %.1f%% of hair pixels changed\n",
           100 * f_dry, 100 * f_wet, 100 * f_changed);
    free(dry.px);
    free(wet.px);
    /* Not blank, not filled with one colour; and wetting visibly changes the hair. */
    if (f_dry < 0.01 || f_wet < 0.01 || f_dry > 0.95 || f_wet > 0.95) return fprintf(stderr, "image_check: no hair in a frame\n"), 1;
    if (f_changed < 0.05) return fprintf(stderr, "image_check: the wet frame looks like the dry one\n"), 1;
    return 0;
}
