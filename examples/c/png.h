/* A dependency-free PNG writer: 8-bit RGB, zlib "stored" (uncompressed) blocks. Larger files
 * than a real deflater makes, but no library to install and nothing to get wrong. */
#ifndef WETHAIR_EXAMPLE_PNG_H
#define WETHAIR_EXAMPLE_PNG_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t png_crc_table[256];

static uint32_t png_crc(uint32_t crc, const uint8_t *p, size_t n) {
    if (!png_crc_table[1]) {
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t c = i;
            for (int k = 0; k < 8; k++) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            png_crc_table[i] = c;
        }
    }
    crc = ~crc;
    for (size_t i = 0; i < n; i++) crc = png_crc_table[(crc ^ p[i]) & 0xff] ^ (crc >> 8);
    return ~crc;
}

static void png_be32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static int png_chunk(FILE *f, const char *type, const uint8_t *data, uint32_t len) {
    uint8_t head[8];
    png_be32(head, len);
    memcpy(head + 4, type, 4);
    uint32_t crc = png_crc(png_crc(0, head + 4, 4), data, len);
    uint8_t tail[4];
    png_be32(tail, crc);
    return fwrite(head, 1, 8, f) == 8 && (len == 0 || fwrite(data, 1, len, f) == len) && fwrite(tail, 1, 4, f) == 4;
}

/* Writes `rgb` (w*h*3 bytes, rows top to bottom) to `path`. Returns 0 on success. */
static int png_write(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h) {
    size_t raw_len = (size_t)h * (3 * (size_t)w + 1);
    size_t blocks = (raw_len + 65534) / 65535;
    size_t z_len = 2 + raw_len + 5 * blocks + 4;
    uint8_t *raw = malloc(raw_len), *z = malloc(z_len);
    if (!raw || !z) return 1;
    for (uint32_t y = 0; y < h; y++) {
        raw[y * (3 * (size_t)w + 1)] = 0; /* filter: none */
        memcpy(raw + y * (3 * (size_t)w + 1) + 1, rgb + (size_t)y * w * 3, 3 * (size_t)w);
    }
    size_t o = 0;
    z[o++] = 0x78;
    z[o++] = 0x01;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < raw_len; i++) {
        a = (a + raw[i]) % 65521;
        b = (b + a) % 65521;
    }
    for (size_t done = 0; done < raw_len;) {
        uint16_t n = (uint16_t)(raw_len - done > 65535 ? 65535 : raw_len - done);
        z[o++] = done + n == raw_len;
        z[o++] = (uint8_t)n;
        z[o++] = (uint8_t)(n >> 8);
        z[o++] = (uint8_t)~n;
        z[o++] = (uint8_t)(~n >> 8);
        memcpy(z + o, raw + done, n);
        o += n;
        done += n;
    }
    png_be32(z + o, (b << 16) | a);
    o += 4;
    uint8_t ihdr[13] = {0};
    png_be32(ihdr, w);
    png_be32(ihdr + 4, h);
    ihdr[8] = 8; /* bit depth */
    ihdr[9] = 2; /* RGB */
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite("\x89PNG\r\n\x1a\n", 1, 8, f) == 8 && png_chunk(f, "IHDR", ihdr, 13) &&
             png_chunk(f, "IDAT", z, (uint32_t)o) && png_chunk(f, "IEND", NULL, 0);
    if (f) ok = (fclose(f) == 0) && ok;
    free(raw);
    free(z);
    return ok ? 0 : 1;
}

#endif
