// placeholder until the render pipeline lands
namespace chcrt {}
