# Standalone Asio with one set of configuration macros for every target that includes it.
#
# Asio picks its inline allocator (std::aligned_alloc or operator new) from whether
# libstdc++'s configuration header happened to be included before its own, so two
# translation units of one program could compile it differently and free with one what
# the other allocated (AddressSanitizer reports the mismatch when an io_context thread
# ends). Disabling the aligned path here makes every unit agree.
add_library(demlink_asio INTERFACE)
target_compile_definitions(demlink_asio INTERFACE ASIO_STANDALONE ASIO_NO_DEPRECATED
                                                  ASIO_DISABLE_STD_ALIGNED_ALLOC)
