using System;
using System.Runtime.InteropServices;

namespace WetHair
{
    /// <summary>A failed wethair call: the C result code and the library's message. The call
    /// wrote nothing (the C API's rule), so the caller's arrays are as they were.</summary>
    public class WetHairException : Exception
    {
        /// <summary>The WETHAIR_ERROR_* code.</summary>
        public Result Code { get; }

        public WetHairException(Result code, string message) : base(message) { Code = code; }

        /// <summary>Throws when <paramref name="r"/> is not Ok, with this thread's last message.</summary>
        internal static void Check(Result r)
        {
            if (r == Result.Ok) return;
            string name = Marshal.PtrToStringAnsi(Native.wethair_result_string((uint)r));
            string msg = Marshal.PtrToStringAnsi(Native.wethair_last_error_message());
            throw new WetHairException(r, name + ": " + msg);
        }
    }
}
