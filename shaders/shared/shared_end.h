#ifdef __cplusplus
} // namespace chcrt::gpu
#endif
