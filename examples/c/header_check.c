/* Compiles the generated header as C11 and (renamed .cpp by the build) as C++17 under
 * -Wall -Wextra -Werror, and checks the def structs' sizes are what the library expects. */
#include "wethair.h"

#include <stdio.h>

int main(void) {
    WetHairSimDesc desc;
    wethair_sim_desc_default(&desc);
    WetHairGroomDesc gdesc;
    wethair_groom_desc_default(&gdesc);
    if (desc.struct_size != sizeof desc || gdesc.struct_size != sizeof gdesc) {
        printf("struct_size mismatch: %u vs %zu\n", desc.struct_size, sizeof desc);
        return 1;
    }
    return wethair_version() == WETHAIR_VERSION ? 0 : 1;
}
