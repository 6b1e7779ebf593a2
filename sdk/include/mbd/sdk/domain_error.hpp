// Thrown by a joint whose bodies have moved where its geometry is not defined (a wheel that
// left its rail head): the message says where the contact went and how far outside the domain
// it is. The core adds the joint's name and the time and stops the run with a DynamicsError
// (constraint_system.cpp), so a plugin need not know either.
#pragma once

#include <mbd/sdk/params.hpp>  // MBD_SDK_API

#include <stdexcept>
#include <string>

namespace mbd {

class MBD_SDK_API DomainError : public std::runtime_error {
public:
    explicit DomainError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace mbd
