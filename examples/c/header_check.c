/* Compiles the generated header as C11 and (renamed .cpp by the build) as C++17 under
 * -Wall -Wextra -Werror, and checks the def structs' sizes are what the library expects:
 * `wethair_sim_desc_init` fills the current layout, `wethair_sim_desc_default` the 0.1.0 one
 * (128 bytes), the other defaults their only layout. */
#include "wethair.h"

#include <stdio.h>

int main(void) {
    WetHairSimDesc desc, old;
    if (wethair_sim_desc_init(&desc, sizeof desc) != WETHAIR_OK) return 1;
    wethair_sim_desc_default(&old);
    WetHairGroomDesc gdesc;
    wethair_groom_desc_default(&gdesc);
    WetHairLoadDesc ldesc;
    wethair_load_desc_default(&ldesc);
    if (desc.struct_size != sizeof desc || old.struct_size != 128 || gdesc.struct_size != sizeof gdesc ||
        ldesc.struct_size != sizeof ldesc) {
        printf("struct_size mismatch: %u vs %zu, %u vs 128\n", desc.struct_size, sizeof desc, old.struct_size);
        return 1;
    }
    if (desc.spring_model != WETHAIR_SPRING_MODEL_MATERIAL || desc.integrator != WETHAIR_INTEGRATOR_AUTO) {
        printf("current defaults: spring model %u, integrator %u\n", desc.spring_model, desc.integrator);
        return 1;
    }
    return wethair_version() == WETHAIR_VERSION ? 0 : 1;
}
