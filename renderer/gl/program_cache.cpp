#include "renderer/gl/program_cache.h"

namespace chcrt {

const ShaderProgram& ProgramCache::get(const std::vector<ShaderStage>& stages, const std::vector<ShaderDefine>& defines) {
    std::string key;
    for (const ShaderStage& s : stages) key += std::to_string(s.type) + ' ' + s.path + '\n';
    // With the implicit defines a program also gets (the context's loop cap, process-wide defines): a program
    // compiled before one of them changed is not the one asked for now.
    for (const ShaderDefine& d : withImplicitDefines(defines)) key += d.name + '=' + d.value + '\n';
    auto it = programs_.find(key);
    if (it == programs_.end()) it = programs_.emplace(std::move(key), ShaderProgram(stages, defines)).first;
    return it->second;
}

} // namespace chcrt
