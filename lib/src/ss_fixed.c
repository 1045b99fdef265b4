#include "ss_fixed.h"
#include "ss_fixed_ops.h"

/* 2^(-i/256) in Q30, rounded to nearest: the exponential's table (1 KB). */
static const uint32_t EXP2_NEG_Q30[256] = {
    1073741824u, 1070838486u, 1067942999u, 1065055341u, 1062175491u, 1059303428u, 1056439131u, 1053582579u,
    1050733751u, 1047892626u, 1045059183u, 1042233401u, 1039415261u, 1036604740u, 1033801819u, 1031006477u,
    1028218693u, 1025438448u, 1022665720u, 1019900489u, 1017142735u, 1014392438u, 1011649578u, 1008914134u,
    1006186087u, 1003465416u, 1000752102u, 998046124u,  995347464u,  992656100u,  989972014u,  987295185u,
    984625594u,  981963222u,  979308048u,  976660054u,  974019220u,  971385527u,  968758955u,  966139485u,
    963527098u,  960921775u,  958323496u,  955732243u,  953147997u,  950570738u,  948000448u,  945437108u,
    942880699u,  940331203u,  937788600u,  935252872u,  932724001u,  930201967u,  927686753u,  925178340u,
    922676710u,  920181844u,  917693724u,  915212331u,  912737649u,  910269657u,  907808339u,  905353676u,
    902905651u,  900464244u,  898029440u,  895601218u,  893179563u,  890764456u,  888355878u,  885953814u,
    883558244u,  881169153u,  878786521u,  876410331u,  874040567u,  871677210u,  869320244u,  866969651u,
    864625413u,  862287515u,  859955938u,  857630665u,  855311680u,  852998965u,  850692504u,  848392279u,
    846098274u,  843810471u,  841528855u,  839253408u,  836984114u,  834720956u,  832463917u,  830212982u,
    827968132u,  825729353u,  823496627u,  821269938u,  819049271u,  816834607u,  814625932u,  812423229u,
    810226483u,  808035676u,  805850792u,  803671817u,  801498734u,  799331526u,  797170178u,  795014675u,
    792865000u,  790721137u,  788583072u,  786450787u,  784324269u,  782203500u,  780088465u,  777979150u,
    775875538u,  773777614u,  771685363u,  769598769u,  767517817u,  765442492u,  763372778u,  761308661u,
    759250125u,  757197155u,  755149737u,  753107854u,  751071493u,  749040637u,  747015274u,  744995386u,
    742980960u,  740971982u,  738968435u,  736970306u,  734977579u,  732990241u,  731008277u,  729031671u,
    727060411u,  725094480u,  723133865u,  721178552u,  719228525u,  717283772u,  715344277u,  713410026u,
    711481005u,  709557200u,  707638598u,  705725183u,  703816941u,  701913860u,  700015924u,  698123120u,
    696235434u,  694352853u,  692475362u,  690602947u,  688735596u,  686873293u,  685016026u,  683163781u,
    681316545u,  679474303u,  677637043u,  675804750u,  673977412u,  672155015u,  670337545u,  668524990u,
    666717336u,  664914570u,  663116678u,  661323648u,  659535466u,  657752119u,  655973594u,  654199878u,
    652430958u,  650666822u,  648907455u,  647152846u,  645402981u,  643657847u,  641917433u,  640181724u,
    638450708u,  636724373u,  635002706u,  633285695u,  631573326u,  629865587u,  628162466u,  626463950u,
    624770026u,  623080683u,  621395908u,  619715688u,  618040012u,  616368866u,  614702239u,  613040119u,
    611382493u,  609729349u,  608080675u,  606436459u,  604796689u,  603161352u,  601530438u,  599903933u,
    598281827u,  596664106u,  595050760u,  593441776u,  591837143u,  590236848u,  588640881u,  587049229u,
    585461881u,  583878825u,  582300049u,  580725543u,  579155293u,  577589290u,  576027521u,  574469975u,
    572916640u,  571367506u,  569822560u,  568281792u,  566745190u,  565212742u,  563684439u,  562160268u,
    560640218u,  559124278u,  557612438u,  556104685u,  554601009u,  553101399u,  551605844u,  550114332u,
    548626854u,  547143398u,  545663953u,  544188508u,  542717053u,  541249576u,  539786068u,  538326517u};

/* exp(-x) = 2^-(x log2 e) = 2^-k 2^(-i/256) e^(-t): k whole, i/256 the fraction's top 8 bits from
 * the table, and t = r ln2 for the fraction's rest r < 2^-8, so t < 2^-8.5 and e^-t = 1 - t + t^2/2
 * - t^3/6 to within t^4/24 < 2^-40. Four 32 x 32 -> 64 products (the Taylor polynomial of degree 7
 * it replaces took 16, and 6 of them by 2^34/n for its divisions: 1 000 instructions an exponential
 * on the M0+, BENCHMARKS.md). */
int32_t ss_exp_neg_q16_q30(int32_t x_q16)
{
    if (x_q16 <= 0) {
        return SS_Q30_ONE;
    }
    /* y = x log2(e) with 46 fraction bits (Q16 x Q30; log2(e) in Q30 = 1549082005), < 2^62 */
    const uint64_t y = ss_mul_u32_u64((uint32_t)x_q16, 1549082005u);
    const uint32_t k = (uint32_t)(y >> 46);
    if (k >= 31u) {
        return 0; /* below 2^-31: zero in Q30 */
    }
    const uint32_t f = (uint32_t)(y >> 16) & (SS_Q30_ONE - 1u); /* the fraction in Q30 */
    const uint32_t r = f & ((1u << 22) - 1u);                   /* below 2^-8 */
    /* t = r ln2 (ln2 in Q30 = 744261118), below 2^21.5 in Q30; t^2 / 2 below 2^13; t^3 / 6 below
     * 4 units: its factor t taken to 14 bits (t / 2^8) changes it by far less than a unit */
    const uint32_t t = (uint32_t)(ss_mul_u32_u64(r, 744261118u) >> 30);
    const uint32_t t2 = (uint32_t)(ss_mul_u32_u64(t, t) >> 31);
    const uint32_t t3 =
        (((t2 * (t >> 8)) >> 22) * 21846u) >> 16;   /* / 3, exact below 2^15 (no divide on the M0+) */
    const uint32_t poly = SS_Q30_ONE - t + t2 - t3; /* e^-t in Q30, in (2^30 0.997, 2^30] */
    /* times 2^(-i/256) and 2^-k, rounded once */
    const uint64_t m = ss_mul_u32_u64(EXP2_NEG_Q30[f >> 22], poly); /* Q60, below 2^60 */
    const int sh = 30 + (int)k;
    return (int32_t)((m + ((uint64_t)1 << (sh - 1))) >> sh);
}

int32_t ss_exp_neg_q32_q30(uint64_t x_q32)
{
    const uint64_t hi = x_q32 >> 16;
    if (hi > (uint64_t)INT32_MAX) {
        return 0;
    }
    const int64_t e_hi = ss_exp_neg_q16_q30((int32_t)hi);
    const uint32_t lo = (uint32_t)(x_q32 & 0xFFFFu); /* units of 2^-32, below 2^-16 */
    /* e_hi * (1 - lo): e_hi * lo < 2^30 * 2^16, no overflow; rounded to nearest */
    return (int32_t)(e_hi - (int64_t)((ss_mul_u32_u64((uint32_t)e_hi, lo) + ((uint64_t)1 << 31)) >> 32));
}

/* Seeds of ss_reciprocal_mantissa_q: 2^24 / (256.5 + i) rounded, 1 / the middle of the i-th of 256
 * equal parts of [1, 2) at 2^-15, within (1/256) / (2 + 1/256) < 2^-9 of 1/x over its part,
 * relative (2^-17 more for the rounding). */
static const uint16_t RECIP_SEED[256] = {
    65408u, 65154u, 64902u, 64652u, 64404u, 64158u, 63913u, 63671u, 63430u, 63191u, 62954u, 62719u, 62485u,
    62253u, 62023u, 61795u, 61568u, 61343u, 61119u, 60897u, 60677u, 60458u, 60241u, 60026u, 59812u, 59599u,
    59388u, 59179u, 58971u, 58764u, 58559u, 58356u, 58153u, 57952u, 57753u, 57555u, 57358u, 57163u, 56968u,
    56776u, 56584u, 56394u, 56205u, 56017u, 55831u, 55646u, 55462u, 55279u, 55098u, 54917u, 54738u, 54560u,
    54383u, 54207u, 54033u, 53859u, 53687u, 53516u, 53346u, 53177u, 53009u, 52842u, 52676u, 52511u, 52347u,
    52184u, 52022u, 51862u, 51702u, 51543u, 51385u, 51228u, 51072u, 50917u, 50763u, 50610u, 50458u, 50306u,
    50156u, 50007u, 49858u, 49710u, 49563u, 49417u, 49272u, 49128u, 48985u, 48842u, 48700u, 48559u, 48419u,
    48280u, 48141u, 48003u, 47867u, 47730u, 47595u, 47460u, 47326u, 47193u, 47061u, 46929u, 46798u, 46668u,
    46539u, 46410u, 46282u, 46155u, 46028u, 45902u, 45777u, 45652u, 45528u, 45405u, 45283u, 45161u, 45040u,
    44919u, 44799u, 44680u, 44561u, 44443u, 44326u, 44209u, 44093u, 43977u, 43862u, 43748u, 43634u, 43521u,
    43408u, 43296u, 43185u, 43074u, 42963u, 42854u, 42744u, 42636u, 42528u, 42420u, 42313u, 42207u, 42101u,
    41996u, 41891u, 41786u, 41683u, 41579u, 41476u, 41374u, 41272u, 41171u, 41070u, 40970u, 40870u, 40771u,
    40672u, 40574u, 40476u, 40378u, 40281u, 40185u, 40089u, 39993u, 39898u, 39804u, 39709u, 39616u, 39522u,
    39429u, 39337u, 39245u, 39153u, 39062u, 38971u, 38881u, 38791u, 38702u, 38613u, 38524u, 38436u, 38348u,
    38260u, 38173u, 38087u, 38000u, 37915u, 37829u, 37744u, 37659u, 37575u, 37491u, 37407u, 37324u, 37241u,
    37159u, 37077u, 36995u, 36914u, 36833u, 36752u, 36672u, 36592u, 36512u, 36433u, 36354u, 36275u, 36197u,
    36119u, 36041u, 35964u, 35887u, 35810u, 35734u, 35658u, 35583u, 35507u, 35432u, 35358u, 35283u, 35209u,
    35136u, 35062u, 34989u, 34916u, 34844u, 34771u, 34700u, 34628u, 34557u, 34486u, 34415u, 34344u, 34274u,
    34204u, 34135u, 34065u, 33996u, 33928u, 33859u, 33791u, 33723u, 33655u, 33588u, 33521u, 33454u, 33387u,
    33321u, 33255u, 33189u, 33124u, 33059u, 32994u, 32929u, 32864u, 32800u};

int32_t ss_reciprocal_mantissa_q(uint32_t d, int *shift)
{
    if (d == 0u || d > (uint32_t)INT32_MAX) {
        *shift = 0;
        return 0;
    }
    /* dn = d 2^n in [2^30, 2^31). Where the core has CLZ (ARMv7-M: the ACLE's feature macro) it is
     * one instruction; elsewhere (the host, ARMv6-M, where __builtin_clz is a libgcc call) a
     * compare tree. The same n either way (the M3 and M0+ images print the same bits) */
#if defined(__ARM_FEATURE_CLZ)
    const int n = __builtin_clz(d) - 1;
    const uint32_t dn = d << n;
#else
    int n = 0;
    uint32_t dn = d;
    if (dn < ((uint32_t)1 << 15)) {
        dn <<= 16;
        n += 16;
    }
    if (dn < ((uint32_t)1 << 23)) {
        dn <<= 8;
        n += 8;
    }
    if (dn < ((uint32_t)1 << 27)) {
        dn <<= 4;
        n += 4;
    }
    if (dn < ((uint32_t)1 << 29)) {
        dn <<= 2;
        n += 2;
    }
    if (dn < ((uint32_t)1 << 30)) {
        dn <<= 1;
        n += 1;
    }
#endif
    /* y0 ~ 2^60 / dn in (2^29, 2^30], in 32-bit products (one instruction on every target): the
     * seed s ~ 2^46 / dn, and a Newton step s + s e / 2^38 on dn's top 23 bits, e = 2^38 - (dn /
     * 2^8) s within 2^29: it is the product's low word (mod 2^32; unsigned wrap-around is defined)
     * taken with an offset 2^31, so that no negative value is shifted. Relative error (2^-9)^2
     * plus the truncations, within 2^-17.7. */
    const uint32_t s = RECIP_SEED[(dn >> 22) - 256u];
    const uint32_t res = ((uint32_t)1 << 31) - (dn >> 8) * s; /* 2^31 + e */
    const uint32_t y0 = (s << 14) + ((s * (res >> 16)) >> 8) - (s << 7);
    /* a Newton step in 32 x 32 -> 64 products, y0 + y0 (1 - dn y0 / 2^60), at the scale 2^61: its
     * residual e = 2^60 - dn y0 is within 2^42.3, u = e / 2^15 + 2^31 fits 32 bits, and y0 e /
     * 2^59 is (y0 u - y0 2^31) / 2^44, rounded, unsigned and below 2^63. What is left: the
     * rounding and (2^-17.7)^2 of y, within 0.6 of 2^61 / dn over every dn */
    const uint32_t u = (uint32_t)((((uint64_t)1 << 60) + ((uint64_t)1 << 46) - ss_mul_u32_u64(dn, y0)) >> 15);
    const uint64_t c =
        ss_mul_u32_u64(y0, u) + (((uint64_t)1 << 61) + ((uint64_t)1 << 43)) - ((uint64_t)y0 << 31);
    const uint64_t y = 2 * (uint64_t)y0 + (c >> 44) - ((uint64_t)1 << 17);
    *shift = 61 - n;
    return (int32_t)((y > (uint64_t)INT32_MAX) ? INT32_MAX : y);
}
