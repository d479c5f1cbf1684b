!> Compressible neo-Hookean hyperelastic material.
!>
!> sigma = mu / J (B - I) + lambda ln(J) / J I, with B = F F^T, J = det F, and the Lame
!> parameters of E and nu. The material follows its own deformation gradient, integrated from
!> the velocity gradient of each step, F_{n+1} = (I + L dt) F_n with L dt = dstrain + Omega,
!> and kept in the particle state as F - I (9 values, so a zero state is the undeformed one).
!> Being hyperelastic, the stress depends only on F: it is objective without a stress rate,
!> and an elastic cycle returns all the work put in. With nu = 0 a uniaxial stretch gives
!> sigma = E/2 (F - 1/F), the law of the manufactured solution of REFERENCES.md section 3.
!>
!> `materials[i].type = "neo_hookean"`, keys `E`, `nu`, `rho` (as a linear elastic solid).
module mpm_material_neo_hookean
    use mpm_kinds, only: wp
    use mpm_material, only: material_key_width
    use mpm_elastic_solid, only: elastic_solid_type, elastic_keys
    implicit none
    private
    public :: neo_hookean_material_type, new_neo_hookean_material

    !> Compressible neo-Hookean solid; E, nu, rho, the Lame parameters, the wave speed and the
    !> summary line come from `elastic_solid_type`.
    type, extends(elastic_solid_type) :: neo_hookean_material_type
    contains
        procedure, nopass :: names => neo_hookean_names
        procedure, nopass :: keys => neo_hookean_keys
        procedure :: update_stress => neo_hookean_update_stress
        procedure :: nstate => neo_hookean_nstate
        procedure :: elastic_energy_block => neo_hookean_elastic_energy_block
    end type neo_hookean_material_type

contains

    !> Names accepted for `type`.
    pure subroutine neo_hookean_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "neo_hookean"]
    end subroutine neo_hookean_names

    !> Keys of a neo-Hookean material.
    pure subroutine neo_hookean_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = elastic_keys
    end subroutine neo_hookean_keys

    !> Construct from E, nu and rho.
    pure subroutine new_neo_hookean_material(mat, name, young, poisson, density)
        type(neo_hookean_material_type), intent(out) :: mat
            !! the material
        character(len=*), intent(in) :: name
            !! material name
        real(wp), intent(in) :: young
            !! Young's modulus [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio [-]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]

        mat%name = name
        call mat%set_elasticity(young, poisson, density)
    end subroutine new_neo_hookean_material

    !> State: the deformation gradient minus the identity, 3 x 3 column by column.
    pure integer function neo_hookean_nstate(self)
        class(neo_hookean_material_type), intent(in) :: self
        neo_hookean_nstate = 9
    end function neo_hookean_nstate

    !> Stored energy per unit current volume, W / J with the energy per reference volume
    !> W = mu/2 (tr(F F^T) - 3) - mu ln J + lambda/2 (ln J)^2 (whose derivative is the stress
    !> of neo_hookean_update_stress), F from the state; 0 for an inverted element.
    pure subroutine neo_hookean_elastic_energy_block(self, n, stress, state, density)
        class(neo_hookean_material_type), intent(in) :: self
        integer, intent(in) :: n
        real(wp), intent(in) :: stress(:, :)
        real(wp), intent(in) :: state(:, :)
        real(wp), intent(out) :: density(:)

        real(wp) :: f(3, 3), jac
        integer :: i, j

        do j = 1, n
            f = reshape(state(1:9, j), [3, 3])
            do i = 1, 3
                f(i, i) = f(i, i) + 1.0_wp
            end do
            jac = f(1, 1)*(f(2, 2)*f(3, 3) - f(2, 3)*f(3, 2)) &
                - f(1, 2)*(f(2, 1)*f(3, 3) - f(2, 3)*f(3, 1)) &
                + f(1, 3)*(f(2, 1)*f(3, 2) - f(2, 2)*f(3, 1))
            density(j) = 0.0_wp
            if (jac > 0.0_wp) density(j) = (0.5_wp*self%shear*(sum(f*f) - 3.0_wp) &
                - self%shear*log(jac) + 0.5_wp*self%lame*log(jac)**2)/jac
        end do
    end subroutine neo_hookean_elastic_energy_block

    pure subroutine neo_hookean_update_stress(self, stress, dstrain, omega, dt, state)
        class(neo_hookean_material_type), intent(in) :: self
        real(wp), intent(inout) :: stress(:)
        real(wp), intent(in) :: dstrain(:)
        real(wp), intent(in) :: omega(3)
        real(wp), intent(in) :: dt
        real(wp), intent(inout) :: state(:)

        real(wp) :: f(3, 3), ldt(3, 3), b(3, 3), jac, de(6)
        integer :: i

        de = 0.0_wp
        de(1:size(dstrain)) = dstrain
        ! L dt = D dt + W dt; omega = (W_xy, W_yz, W_zx) dt
        ldt = reshape([de(1), de(4) - omega(1), de(6) + omega(3), &
                       de(4) + omega(1), de(2), de(5) - omega(2), &
                       de(6) - omega(3), de(5) + omega(2), de(3)], [3, 3])
        f = reshape(state(1:9), [3, 3])
        do i = 1, 3
            f(i, i) = f(i, i) + 1.0_wp
        end do
        f = f + matmul(ldt, f)
        jac = f(1, 1)*(f(2, 2)*f(3, 3) - f(2, 3)*f(3, 2)) &
            - f(1, 2)*(f(2, 1)*f(3, 3) - f(2, 3)*f(3, 1)) &
            + f(1, 3)*(f(2, 1)*f(3, 2) - f(2, 2)*f(3, 1))
        if (.not. (jac > 0.0_wp)) then
            ! an inverted element: keep the last stress rather than take log of a negative
            return
        end if
        b = matmul(f, transpose(f))
        b = self%shear/jac*b
        do i = 1, 3
            b(i, i) = b(i, i) - self%shear/jac + self%lame*log(jac)/jac
        end do
        if (size(stress) == 4) then
            stress = [b(1, 1), b(2, 2), b(3, 3), b(1, 2)]
        else
            stress = [b(1, 1), b(2, 2), b(3, 3), b(1, 2), b(2, 3), b(3, 1)]
        end if
        do i = 1, 3
            f(i, i) = f(i, i) - 1.0_wp
        end do
        state(1:9) = reshape(f, [9])
    end subroutine neo_hookean_update_stress

end module mpm_material_neo_hookean
