/* The host's own glad entry points, as a host that generated its own loader has them (the
   parameter types do not matter to the linker). They count their calls and load nothing. */
int host_glad_calls = 0;

int gladLoadGLContextUserPtr(void* context, void* load, void* userptr) {
  (void)context, (void)load, (void)userptr;
  ++host_glad_calls;
  return 0;
}

int gladLoadGLContext(void* context, void* load) {
  (void)context, (void)load;
  ++host_glad_calls;
  return 0;
}
