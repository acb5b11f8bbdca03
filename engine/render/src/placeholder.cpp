// Placeholder until the module lands; delete when adding real sources.
namespace polder { [[maybe_unused]] static int placeholder_engine_render; }
