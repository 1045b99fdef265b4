/* A deliberate float use: the symbol check must reject this image, or it proves nothing. */
#include <stdint.h>

void SysTick_Handler(void);
void SysTick_Handler(void)
{
}

static volatile float a = 1.5f;
static volatile int32_t out;

int main(void)
{
    out = (int32_t)(a * 3.0f);
    return 0;
}
