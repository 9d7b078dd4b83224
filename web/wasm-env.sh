# Sourced by web/build.sh, and by hand before other cargo commands for wasm32
# (`. web/wasm-env.sh; cargo clippy --target wasm32-unknown-unknown -p seamlit-web`).
# meshopt 0.7.0 compiles meshoptimizer for wasm32 against its own small math.h, which lacks
# floorf, ceilf, frexpf, log2f and a few more (used by parts seamlit never calls: quantization,
# opacity maps): name the compiler's builtins instead. Exported here, not in
# .cargo/config.toml's [env], which would change every native build's fingerprint too.
builtins="-Dfloorf=__builtin_floorf -Dfloor=__builtin_floor -Dceilf=__builtin_ceilf"
builtins+=" -Dceil=__builtin_ceil -Dsqrt=__builtin_sqrt -Dcosf=__builtin_cosf -Dlog2f=__builtin_log2f"
builtins+=" -Dfrexpf=__builtin_frexpf -Dldexpf=__builtin_ldexpf -Dldexp=__builtin_ldexp"
export CFLAGS_wasm32_unknown_unknown="$builtins" CXXFLAGS_wasm32_unknown_unknown="$builtins"
