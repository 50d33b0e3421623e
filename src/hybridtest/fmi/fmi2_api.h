/* The FMI 2.0 C interface for co-simulation, as the importer and our test FMUs use it.
 *
 * Written for hybridtest from the text of the standard: "Functional Mock-up Interface for
 * Model Exchange and Co-Simulation, Version 2.0" (Modelica Association), section 2.1.2
 * (platform-dependent types: fmi2Real is double, fmi2Integer and fmi2Boolean are int,
 * fmi2String is a const char*), 2.1.3 (status returned by functions), 2.1.4 (inquire
 * version and platform), 2.1.5 (creation, destruction and logging of an instance, with the
 * callback functions), 2.1.6 (initialization, termination and resetting), 2.1.7 (getting and
 * setting variable values), 2.1.8 (getting and setting the complete FMU state) and 4.2
 * (co-simulation: fmi2DoStep, fmi2CancelStep, status inquiry). No header of the standard's
 * distribution was copied; only the declarations hybridtest needs are here.
 *
 * A binary FMU exports these functions by their plain names (fmi2DoStep, ...) from
 * binaries/linux64/<modelIdentifier>.so; the importer finds them with dlsym. The typedefs
 * fmi2XxxTYPE are the function types used for that lookup. Plain C: the test FMUs include it.
 */
#ifndef HYBRIDTEST_FMI_FMI2_API_H_
#define HYBRIDTEST_FMI_FMI2_API_H_

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* 2.1.2: types. */
typedef void* fmi2Component;            /* an instance of the FMU */
typedef void* fmi2ComponentEnvironment; /* the importer's pointer, passed back to callbacks */
typedef void* fmi2FMUstate;             /* a copy of the complete FMU state */
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char* fmi2String;
typedef char fmi2Byte;

#define fmi2True 1
#define fmi2False 0

/* 2.1.3: status. */
typedef enum {
  fmi2OK,
  fmi2Warning,
  fmi2Discard,
  fmi2Error,
  fmi2Fatal,
  fmi2Pending
} fmi2Status;

/* 2.1.5: what an instance is instantiated for. */
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;

/* 2.1.5: the importer's callbacks. The logger is printf-like: `message` is a format and the
 * variadic arguments its values. */
typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment environment, fmi2String instanceName,
                                   fmi2Status status, fmi2String category, fmi2String message,
                                   ...);
typedef void* (*fmi2CallbackAllocateMemory)(size_t nobj, size_t size);
typedef void (*fmi2CallbackFreeMemory)(void* obj);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment environment, fmi2Status status);

typedef struct {
  const fmi2CallbackLogger logger;
  const fmi2CallbackAllocateMemory allocateMemory;
  const fmi2CallbackFreeMemory freeMemory;
  const fmi2StepFinished stepFinished; /* NULL: fmi2DoStep returns only when done */
  const fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

/* 4.2.3: what fmi2GetStatus and friends are asked about. */
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated } fmi2StatusKind;

/* 2.1.4 */
typedef const char* fmi2GetTypesPlatformTYPE(void);
typedef const char* fmi2GetVersionTYPE(void);
/* 2.1.5 */
typedef fmi2Status fmi2SetDebugLoggingTYPE(fmi2Component c, fmi2Boolean loggingOn,
                                           size_t nCategories, const fmi2String categories[]);
typedef fmi2Component fmi2InstantiateTYPE(fmi2String instanceName, fmi2Type fmuType,
                                          fmi2String fmuGUID, fmi2String fmuResourceLocation,
                                          const fmi2CallbackFunctions* functions,
                                          fmi2Boolean visible, fmi2Boolean loggingOn);
typedef void fmi2FreeInstanceTYPE(fmi2Component c);
/* 2.1.6 */
typedef fmi2Status fmi2SetupExperimentTYPE(fmi2Component c, fmi2Boolean toleranceDefined,
                                           fmi2Real tolerance, fmi2Real startTime,
                                           fmi2Boolean stopTimeDefined, fmi2Real stopTime);
typedef fmi2Status fmi2EnterInitializationModeTYPE(fmi2Component c);
typedef fmi2Status fmi2ExitInitializationModeTYPE(fmi2Component c);
typedef fmi2Status fmi2TerminateTYPE(fmi2Component c);
typedef fmi2Status fmi2ResetTYPE(fmi2Component c);
/* 2.1.7 */
typedef fmi2Status fmi2GetRealTYPE(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   fmi2Real value[]);
typedef fmi2Status fmi2GetIntegerTYPE(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t nvr, fmi2Integer value[]);
typedef fmi2Status fmi2GetBooleanTYPE(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t nvr, fmi2Boolean value[]);
typedef fmi2Status fmi2SetRealTYPE(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[]);
typedef fmi2Status fmi2SetIntegerTYPE(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t nvr, const fmi2Integer value[]);
typedef fmi2Status fmi2SetBooleanTYPE(fmi2Component c, const fmi2ValueReference vr[],
                                      size_t nvr, const fmi2Boolean value[]);
/* 2.1.8 */
typedef fmi2Status fmi2GetFMUstateTYPE(fmi2Component c, fmi2FMUstate* FMUstate);
typedef fmi2Status fmi2SetFMUstateTYPE(fmi2Component c, fmi2FMUstate FMUstate);
typedef fmi2Status fmi2FreeFMUstateTYPE(fmi2Component c, fmi2FMUstate* FMUstate);
typedef fmi2Status fmi2SerializedFMUstateSizeTYPE(fmi2Component c, fmi2FMUstate FMUstate,
                                                  size_t* size);
typedef fmi2Status fmi2SerializeFMUstateTYPE(fmi2Component c, fmi2FMUstate FMUstate,
                                             fmi2Byte serializedState[], size_t size);
typedef fmi2Status fmi2DeSerializeFMUstateTYPE(fmi2Component c,
                                               const fmi2Byte serializedState[], size_t size,
                                               fmi2FMUstate* FMUstate);
/* 4.2.2 */
typedef fmi2Status fmi2DoStepTYPE(fmi2Component c, fmi2Real currentCommunicationPoint,
                                  fmi2Real communicationStepSize,
                                  fmi2Boolean noSetFMUStatePriorToCurrentPoint);
typedef fmi2Status fmi2CancelStepTYPE(fmi2Component c);
/* 4.2.3 */
typedef fmi2Status fmi2GetStatusTYPE(fmi2Component c, const fmi2StatusKind s,
                                     fmi2Status* value);

#ifdef __cplusplus
}
#endif

#endif /* HYBRIDTEST_FMI_FMI2_API_H_ */
