!> A viscous absorbing face (Lysmer and Kuhlemeyer 1969): dashpots that take the traction
!> t_n = -rho vp v_n normal to the face and t_t = -rho vs v_t along it, which is what the
!> material beyond the face would give a plane wave leaving the domain at normal incidence,
!> so that such a wave passes out instead of reflecting.
!>
!> On the grid a face node stands for the face area its material covers: with the material's
!> density rho at the face, a node of mass m holds rho A dx / 2 (the half of its cell inside
!> the domain), so A = 2 m / (rho dx) and the dashpot of the node is c = rho v A = 2 m v / dx,
!> whatever the density; a node the material only partly covers gets the share it covers.
!> The dashpot is applied implicitly, m (v - v*) = -dt c v with v* the velocity of the nodal
!> update: v = v* / (1 + 2 v dt / dx), stable at any time step and any nodal mass. The energy
!> it takes, booked with what the faces stop (`boundary_work`: it leaves the domain, it is
!> not work of the loads), is its impulse at the mean velocity of the step,
!> -m (v - v*) . (v0 + v) / 2 with v0 = v* - dt a* the velocity at the start of the step, as
!> the nodal update books the work of damping. A component another face holds (the corner
!> with a fixed or velocity face) is left as that face sets it.
!>
!> The area of a node is exact where the face node holds half a cell of the material, as with
!> the linear and cpGIMP shape functions; the boundary-modified B-splines give the face node
!> 13/24 (bspline2) and 7/12 (bspline3) of a cell, so their dashpots are 8 % and 17 % too
!> stiff, which reflects about 0.2 % and 0.6 % of a wave's energy (R^2, R = (c - Z)/(c + Z)).
!>
!> A plain dashpot holds no static load: under gravity the material on an absorbing base
!> sinks at the speed the dashpot needs to carry its weight (a known limit of viscous
!> boundaries). A Kelvin-Voigt face (`kn`, `kt`) adds springs per unit area beside the
!> dashpots, -k A u with u the node's displacement since the start (kept by the grid,
!> `grid%acting_disp`, and by checkpoints) and A the face area the node stands for, which
!> the grid gives (the springs do not take the area from the nodal mass, which grows when
!> the loaded material's particles settle past the face); implicit in v and u together,
!> v = (v* - (k A dt^2 / m) u / dt) / (1 + c dt / m + k A dt^2 / m), u += dt v. It holds a
!> static load q after settling by q / kn. Particles moved past the face are put back on it.
module mpm_boundary_absorbing
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: absorbing_boundary_type

    !> Normal and tangential dashpots of the impedances of the material beyond the face.
    type, extends(boundary_type) :: absorbing_boundary_type
        real(wp) :: vp = 0.0_wp
            !! P-wave speed of the material beyond the face, sqrt((K + 4 G / 3) / rho) [m/s]
        real(wp) :: vs = 0.0_wp
            !! S-wave speed, sqrt(G / rho) [m/s]
        real(wp) :: kn = 0.0_wp
            !! stiffness per unit area of the springs normal to the face [Pa/m]: with kt, a
            !! Kelvin-Voigt face (springs beside the dashpots); 0: none
        real(wp) :: kt = 0.0_wp
            !! stiffness per unit area of the springs along the face [Pa/m]
    contains
        procedure, nopass :: names => absorbing_names
        procedure, nopass :: keys => absorbing_keys
        procedure, nopass :: example => absorbing_example
        procedure, nopass :: purpose => absorbing_purpose
        procedure, nopass :: needs => absorbing_needs
        procedure :: read => absorbing_read
        procedure :: summary => absorbing_summary
        procedure :: nodes => absorbing_nodes
        procedure :: act => absorbing_act
    end type absorbing_boundary_type

contains

    !> "absorbing"
    pure subroutine absorbing_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "absorbing"]
    end subroutine absorbing_names

    !> "vp", "vs", "kn", "kt"
    pure subroutine absorbing_keys(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=boundary_key_width) :: "vp", "vs", "kn", "kt"]
    end subroutine absorbing_keys

    !> The object form, for messages.
    pure function absorbing_example() result(text)
        character(len=:), allocatable :: text
            !! an example face object

        text = '{"type": "absorbing", "vp": 300, "vs": 160} (with "kn", "kt": a ' &
            //"Kelvin-Voigt face)"
    end function absorbing_example

    !> What it is for, for messages.
    pure function absorbing_purpose() result(text)
        character(len=:), allocatable :: text
            !! "a face ..."

        text = "a face through which waves leave the domain"
    end function absorbing_purpose

    !> What the name alone lacks.
    pure function absorbing_needs() result(text)
        character(len=:), allocatable :: text
            !! the missing parameters

        text = "the P- and S-wave speeds vp and vs"
    end function absorbing_needs

    !> `vp` and `vs`, required, above 0 [m/s]; vs below sqrt(3)/2 vp (a material with a
    !> positive bulk modulus, nu > -1, has vs / vp < sqrt(3)/2).
    subroutine absorbing_read(self, face, dim, error)
        class(absorbing_boundary_type), intent(inout) :: self
            !! the condition
        type(cursor_type), intent(in) :: face
            !! the face object, its keys checked
        integer, intent(in) :: dim
            !! space dimensions
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call face%get_real("vp", self%vp, error, required=.true., above=0.0_wp, unit="m/s")
        if (allocated(error)) return
        call face%get_real("vs", self%vs, error, required=.true., above=0.0_wp, unit="m/s")
        if (allocated(error)) return
        if (self%vs >= sqrt(0.75_wp)*self%vp) then
            call face%fail(error, face%key_path("vs")//" = "//fmt_real(self%vs)//" m/s is not "// &
                "below sqrt(3)/2 vp = "//fmt_real(sqrt(0.75_wp)*self%vp)//" m/s: the S-wave "// &
                "speed of a material of positive bulk modulus is below that (vs / vp = "// &
                "sqrt((1 - 2 nu) / (2 (1 - nu))) < sqrt(3)/2 for nu > -1)")
            return
        end if
        if (face%has("kn") .neqv. face%has("kt")) then
            call face%fail(error, face%key_path(trim(merge("kn", "kt", face%has("kn")))) &
                //" is given without "//trim(merge("kt", "kn", face%has("kn")))//": a " &
                //"Kelvin-Voigt face has springs normal (kn) and along (kt) the face, both " &
                //"stiffnesses per unit area [Pa/m], e.g. alpha G / R with R the distance to " &
                //"the source, alpha 1 and 1/2 in 2D, 4/3 and 2/3 in 3D")
            return
        end if
        call face%get_real("kn", self%kn, error, above=0.0_wp, unit="Pa/m")
        if (allocated(error)) return
        call face%get_real("kt", self%kt, error, above=0.0_wp, unit="Pa/m")
    end subroutine absorbing_read

    !> " (vp = 300 m/s, vs = 160 m/s)"
    pure function absorbing_summary(self) result(text)
        class(absorbing_boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! the words after the name

        text = " (vp = "//fmt_real(self%vp)//" m/s, vs = "//fmt_real(self%vs)//" m/s"
        if (self%kn > 0.0_wp) then
            text = text//"; Kelvin-Voigt springs kn = "//fmt_real(self%kn)//" Pa/m, kt = " &
                //fmt_real(self%kt)//" Pa/m)"
        else
            text = text//")"
        end if
    end function absorbing_summary

    !> Nothing held: the face acts on its nodes after the nodal update; a wall.
    pure function absorbing_nodes(self, axis, dim) result(nodes)
        class(absorbing_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%acts = .true.
        nodes%keeps_particles = .true.
        nodes%springs = self%kn > 0.0_wp
    end function absorbing_nodes

    !> The dashpots, implicit: v = v* / (1 + 2 v_wave dt / dx) per component, vp normal to
    !> the face and vs along it, the held components left alone; the energy taken is the
    !> impulse at the mean velocity of the step.
    pure subroutine absorbing_act(self, axis, dim, time, dt, dx, mass, area, held, momentum, &
        velocity, acceleration, displacement, taken, given)
        class(absorbing_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: time
            !! time at the start of the step [s] (the dashpots do not change in time)
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: dx
            !! grid spacing [m]
        real(wp), intent(in) :: mass(:)
            !! mass of each node of the face (n) [kg]
        real(wp), intent(in) :: area(:)
            !! face area each node stands for (n) [m2; m in 2D]
        logical, intent(in) :: held(:, :)
            !! components another face holds (dim, n)
        real(wp), intent(inout) :: momentum(:, :)
            !! momentum (dim, n) [kg m/s]
        real(wp), intent(inout) :: velocity(:, :)
            !! velocity (dim, n) [m/s]
        real(wp), intent(inout) :: acceleration(:, :)
            !! acceleration of the step (dim, n) [m/s2]
        real(wp), intent(inout) :: displacement(:, :)
            !! displacement of each node since the start (dim, n) [m]: the state of a law
            !! with springs, which updates it; the others leave it alone
        real(wp), intent(out) :: taken
            !! energy the dashpots took in this step [J]
        real(wp), intent(out) :: given
            !! the work brought in from outside, which is none here (zero) [J]

        real(wp) :: factor(3), v(3), v0(3), damper(3), spring(3)
        integer :: i

        given = 0.0_wp
        factor = 1.0_wp/(1.0_wp + 2.0_wp*self%vs*dt/dx)
        factor(axis) = 1.0_wp/(1.0_wp + 2.0_wp*self%vp*dt/dx)
        taken = 0.0_wp
        if (self%kn > 0.0_wp) then
            ! Kelvin-Voigt: c / m = 2 v / dx (the dashpots, as below) and k dt^2 / m = k A
            ! dt^2 / m per component (the springs, of the node's face area A), implicit in v
            ! and u
            damper = 2.0_wp*self%vs*dt/dx
            damper(axis) = 2.0_wp*self%vp*dt/dx
            do i = 1, size(mass)
                spring = self%kt*area(i)*dt**2/mass(i)
                spring(axis) = self%kn*area(i)*dt**2/mass(i)
                v(1:dim) = merge(velocity(:, i), (velocity(:, i) - spring(1:dim)/dt &
                    *displacement(:, i))/(1.0_wp + damper(1:dim) + spring(1:dim)), held(:, i))
                v0(1:dim) = velocity(:, i) - dt*acceleration(:, i)
                taken = taken - 0.5_wp*mass(i)*dot_product(v(1:dim) - velocity(:, i), &
                    v0(1:dim) + v(1:dim))
                acceleration(:, i) = acceleration(:, i) + (v(1:dim) - velocity(:, i))/dt
                velocity(:, i) = v(1:dim)
                momentum(:, i) = mass(i)*v(1:dim)
                displacement(:, i) = displacement(:, i) + dt*v(1:dim)
            end do
            return
        end if
        do i = 1, size(mass)
            v(1:dim) = merge(velocity(:, i), factor(1:dim)*velocity(:, i), held(:, i))
            v0(1:dim) = velocity(:, i) - dt*acceleration(:, i)
            taken = taken - 0.5_wp*mass(i)*dot_product(v(1:dim) - velocity(:, i), &
                v0(1:dim) + v(1:dim))
            acceleration(:, i) = acceleration(:, i) + (v(1:dim) - velocity(:, i))/dt
            velocity(:, i) = v(1:dim)
            momentum(:, i) = mass(i)*v(1:dim)
        end do
    end subroutine absorbing_act

end module mpm_boundary_absorbing
