// SafeHandles: the native objects are freed exactly once, also when a finaliser runs.
using System;
using System.Runtime.InteropServices;

namespace WetHair
{
    /// <summary>Owns a WetHairGroom.</summary>
    public sealed class GroomHandle : SafeHandle
    {
        public GroomHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid => handle == IntPtr.Zero;
        protected override bool ReleaseHandle()
        {
            Native.wethair_groom_destroy(handle);
            return true;
        }
    }

    /// <summary>Owns a WetHairSim (its worker threads and GPU objects go with it).</summary>
    public sealed class SimulationHandle : SafeHandle
    {
        public SimulationHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid => handle == IntPtr.Zero;
        protected override bool ReleaseHandle()
        {
            Native.wethair_sim_destroy(handle);
            return true;
        }
    }
}
