/* The installed C ABI from C: the header compiles as C, the library links, and a call that
 * must fail (bytes that are not a .mrig) fails with its status and message. */
#include <stdio.h>
#include <string.h>

#include "capi/mimetic_c.h"

int main(void) {
  const char junk[64] = "not a compiled rig";
  mimetic_rig* rig = NULL;
  const mimetic_status s = mimetic_rig_load_memory(junk, sizeof junk, &rig);
  if (mimetic_api_version() != MIMETIC_C_API_VERSION) return 2;
  if (s != MIMETIC_ERROR_FORMAT || rig != NULL || strstr(mimetic_last_error(), "tag") == NULL)
    return 3;
  printf("consumer_c: %s: %s\n", mimetic_status_name(s), mimetic_last_error());
  return 0;
}
