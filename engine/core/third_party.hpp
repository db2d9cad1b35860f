#pragma once
// Around a third-party header compiled into the program (stb): its code is not ours to warn about
// under the project's -Werror.
#define IKEBANA_THIRD_PARTY_BEGIN                                                                                                  \
    _Pragma("GCC diagnostic push") _Pragma("GCC diagnostic ignored \"-Wconversion\"") _Pragma("GCC diagnostic ignored \"-Wsign-conversion\"") \
        _Pragma("GCC diagnostic ignored \"-Wshadow\"") _Pragma("GCC diagnostic ignored \"-Wmissing-field-initializers\"")                 \
            _Pragma("GCC diagnostic ignored \"-Wunused-function\"") _Pragma("GCC diagnostic ignored \"-Wdouble-promotion\"")
#define IKEBANA_THIRD_PARTY_END _Pragma("GCC diagnostic pop")
