/* SS_FORCE_INLINE (not public API): a static function inlined at every call, where a call would
 * cost more than the body (the parts of a step that a batch interleaves and a single step runs in
 * turn, ss_actuator_f32.c). A plain static inline where the compiler has no such attribute.
 * SS_NOINLINE: a static function kept out of line, a rare path that would grow its caller's
 * common one (ss_actuator_q.c, the turn inside a step). */
#ifndef SS_INLINE_H
#define SS_INLINE_H

#if defined(__GNUC__) || defined(__clang__)
#define SS_FORCE_INLINE static inline __attribute__((always_inline))
#define SS_NOINLINE static __attribute__((noinline))
#else
#define SS_FORCE_INLINE static inline
#define SS_NOINLINE static
#endif

#endif /* SS_INLINE_H */
